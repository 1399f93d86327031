// Test stub of vecmath.jar.
package javax.vecmath;

public class Color3f {
    public float x;
    public float y;
    public float z;

    public Color3f() {
    }

    public Color3f(float x, float y, float z) {
        this.x = x;
        this.y = y;
        this.z = z;
    }

    public final void set(Color3f c) {
        x = c.x;
        y = c.y;
        z = c.z;
    }

    /** Every component within epsilon of c's, compared in floats. */
    public boolean epsilonEquals(Color3f c, float epsilon) {
        float[] d = {x - c.x, y - c.y, z - c.z};
        for (float v : d) {
            if (Float.isNaN(v) || (v < 0 ? -v : v) > epsilon) {
                return false;
            }
        }
        return true;
    }
}
