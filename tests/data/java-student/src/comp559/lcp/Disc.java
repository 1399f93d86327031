// The tests' student-like simulator: a bounding disc in a body's frame (see Bug.java).
package comp559.lcp;

import java.util.ArrayList;
import java.util.Collection;
import javax.vecmath.Point2d;

public class Disc {
    /** Centre, body frame. */
    Point2d cB = new Point2d();

    /** Centre, world frame (updatecW). */
    Point2d cW = new Point2d();

    /** Radius: the blocks' centres' smallest circle plus a block's radius. */
    double r;

    RigidBody body;

    public Disc(Collection<Block> blocks, RigidBody body) {
        this.body = body;
        ArrayList<Point2d> points = new ArrayList<Point2d>();
        for (Block b : blocks) {
            points.add(new Point2d(b.pB.x, b.pB.y));
        }
        MinimumEnclosingCircle mec = new MinimumEnclosingCircle(points);
        cB.set(mec.centre);
        r = mec.radius + Block.radius;
        updatecW();
    }

    public void updatecW() {
        body.toWorld(cB, cW);
    }

    public boolean intersects(Disc d) {
        return cW.distanceSquared(d.cW) < (r + d.r) * (r + d.r);
    }
}
