// The tests' student-like simulator: the system and its step (see Bug.java). Per call of
// advanceTime(h): gravity into the force accumulators, the collision processor (contacts at the
// current positions; the velocity-level solve), then each body's symplectic Euler step.
package comp559.lcp;

import java.util.ArrayList;
import javax.vecmath.Vector2d;
import mintools.parameters.BooleanParameter;
import mintools.parameters.DoubleParameter;

public class RigidBodySystem {
    public String name = "";
    public double simulationTime = 0;
    public ArrayList<RigidBody> bodies = new ArrayList<RigidBody>();
    public CollisionProcessor collisionProcessor = new CollisionProcessor(bodies);
    public MouseSpringForce mouseSpring;
    BooleanParameter useGravity = new BooleanParameter("enable gravity", true);
    DoubleParameter gravityAmount = new DoubleParameter("gravitational constant", 1, -20, 20);
    DoubleParameter gravityAngle = new DoubleParameter("gravity angle", 90, 0, 360);
    private BooleanParameter processCollisions = new BooleanParameter("process collisions", true);

    public void advanceTime(double dt) {
        mouseSpring.apply();
        if (useGravity.getValue()) {
            double theta = gravityAngle.getValue() / 180.0 * Math.PI;
            for (RigidBody b : bodies) {
                Vector2d f = new Vector2d(Math.cos(theta), Math.sin(theta));
                f.scale(b.massLinear * gravityAmount.getValue());
                b.force.add(f);
            }
        }
        if (processCollisions.getValue()) {
            collisionProcessor.processCollisions(dt);
        }
        for (RigidBody b : bodies) {
            b.advanceTime(dt);
        }
        simulationTime += dt;
    }

    public void reset() {
        for (RigidBody b : bodies) {
            b.reset();
        }
        simulationTime = 0;
        collisionProcessor.reset();
    }

    public void clear() {
        bodies.clear();
        RigidBody.nextIndex = 0;
        reset();
    }
}
