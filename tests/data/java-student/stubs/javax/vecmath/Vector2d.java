// Test stub of vecmath.jar.
package javax.vecmath;

public class Vector2d extends Tuple2d {
    public Vector2d() {
    }

    public Vector2d(double x, double y) {
        super(x, y);
    }

    public final double dot(Vector2d v) {
        return x * v.x + y * v.y;
    }

    public final double lengthSquared() {
        return x * x + y * y;
    }

    public final double length() {
        return Math.sqrt(lengthSquared());
    }

    public final void normalize() {
        double norm = 1.0 / Math.sqrt(x * x + y * y);
        x *= norm;
        y *= norm;
    }
}
