// The tests' student-like simulator: one pixel of a body (see Bug.java).
package comp559.lcp;

import javax.vecmath.Color3f;
import javax.vecmath.Point2d;

public class Block {
    /** Radius of the disc around a block: the unit square's circumscribed circle. */
    static double radius = Math.sqrt(2) * 0.5;

    /** Colour, channels in [0, 1]. */
    Color3f c = new Color3f();

    /** Image row. */
    int i;

    /** Image column. */
    int j;

    /** Centre in the body frame. */
    Point2d pB = new Point2d();

    public Block(int i, int j, Color3f c) {
        this.i = i;
        this.j = j;
        this.c.set(c);
    }

    /** The assignment's mass from the colour: 1 − (0.3 r + 0.59 g + 0.11 b). */
    public double getColourMass() {
        return 1 - (0.3 * c.x + 0.59 * c.y + 0.11 * c.z);
    }
}
