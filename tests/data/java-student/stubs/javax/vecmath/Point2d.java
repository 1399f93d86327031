// Test stub of vecmath.jar.
package javax.vecmath;

public class Point2d extends Tuple2d {
    public Point2d() {
    }

    public Point2d(double x, double y) {
        super(x, y);
    }

    public Point2d(Point2d p) {
        super(p.x, p.y);
    }

    public final double distanceSquared(Point2d p) {
        double dx = x - p.x, dy = y - p.y;
        return dx * dx + dy * dy;
    }

    public final double distance(Point2d p) {
        return Math.sqrt(distanceSquared(p));
    }
}
