// The tests' student-like simulator: the smallest circle around points (see Bug.java),
// incremental in the points' order (two and three boundary points).
package comp559.lcp;

import java.util.List;
import javax.vecmath.Point2d;

class MinimumEnclosingCircle {
    final Point2d centre = new Point2d();
    double radius;

    MinimumEnclosingCircle(List<Point2d> points) {
        int n = points.size();
        set(points.get(0), 0);
        for (int i = 1; i < n; i++) {
            Point2d p = points.get(i);
            if (contains(p)) {
                continue;
            }
            set(p, 0);
            for (int j = 0; j < i; j++) {
                Point2d q = points.get(j);
                if (contains(q)) {
                    continue;
                }
                diameter(p, q);
                for (int k = 0; k < j; k++) {
                    Point2d r = points.get(k);
                    if (!contains(r)) {
                        through(p, q, r);
                    }
                }
            }
        }
    }

    private void set(Point2d c, double r) {
        centre.set(c);
        radius = r;
    }

    private boolean contains(Point2d p) {
        return centre.distance(p) <= radius * (1 + 1e-12) + 1e-12;
    }

    private void diameter(Point2d a, Point2d b) {
        centre.interpolate(a, b, 0.5);
        radius = a.distance(b) / 2;
    }

    private void through(Point2d a, Point2d b, Point2d c) {
        double ux = b.x - a.x, uy = b.y - a.y, wx = c.x - a.x, wy = c.y - a.y;
        double d = 2 * (ux * wy - uy * wx);
        double uu = ux * ux + uy * uy, ww = wx * wx + wy * wy;
        if (Math.abs(d) <= 1e-12 * Math.max(uu, ww)) {
            // Collinear: the farthest pair as diameter.
            double ab = uu, ac = ww, bc = b.distanceSquared(c);
            if (ab >= ac && ab >= bc) {
                diameter(a, b);
            } else if (ac >= bc) {
                diameter(a, c);
            } else {
                diameter(b, c);
            }
            return;
        }
        double ox = (wy * uu - uy * ww) / d, oy = (ux * ww - wx * uu) / d;
        centre.set(a.x + ox, a.y + oy);
        radius = Math.sqrt(ox * ox + oy * oy);
    }
}
