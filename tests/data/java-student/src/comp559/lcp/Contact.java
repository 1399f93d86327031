// The tests' student-like simulator: a contact (see Bug.java). Its normal points from body 1's
// block towards body 2's, the starter's convention, so the rows measure body 2's point's velocity
// relative to body 1's: J = [−n, −(r1 × n) | n, r2 × n] and likewise with t = (−n_y, n_x).
package comp559.lcp;

import javax.vecmath.Point2d;
import javax.vecmath.Vector2d;

public class Contact {
    static public int nextContactIndex = 0;
    int index;
    RigidBody body1;
    RigidBody body2;
    Vector2d normal = new Vector2d();
    Point2d contactW = new Point2d();

    /** The normal row and the tangent row, [vx1, vy1, ω1, vx2, vy2, ω2]. */
    double[] jacobianNormal;
    double[] jacobianTangent;

    public Contact(RigidBody body1, RigidBody body2, Point2d contactW, Vector2d normal) {
        this.body1 = body1;
        this.body2 = body2;
        this.contactW.set(contactW);
        this.normal.set(normal);
        index = nextContactIndex++;
        jacobianNormal = rows(normal.x, normal.y);
        jacobianTangent = rows(-normal.y, normal.x);
        if (Bug.is("jacobian_entry")) {
            jacobianNormal[2] = -jacobianNormal[2]; // n × r1 for r1 × n
        }
    }

    private double[] rows(double dx, double dy) {
        double r1x = contactW.x - body1.x.x, r1y = contactW.y - body1.x.y;
        double r2x = contactW.x - body2.x.x, r2y = contactW.y - body2.x.y;
        return new double[] {-dx, -dy, -(r1x * dy - r1y * dx), dx, dy, r2x * dy - r2y * dx};
    }
}
