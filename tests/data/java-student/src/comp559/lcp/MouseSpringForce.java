// The tests' student-like simulator: the mouse spring, inactive until a body is picked.
package comp559.lcp;

import javax.vecmath.Point2d;

public class MouseSpringForce {
    private RigidBody picked;
    private final Point2d point;

    public MouseSpringForce(Point2d point) {
        this.point = point;
    }

    public void setPicked(RigidBody picked) {
        this.picked = picked;
    }

    public void apply() {
        if (picked == null) {
            return;
        }
        throw new IllegalStateException("no mouse in the tests: " + point);
    }
}
