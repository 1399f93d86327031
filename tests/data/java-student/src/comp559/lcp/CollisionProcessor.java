// The tests' student-like simulator: contacts and their velocity-level solve (see Bug.java).
// Detection: body pairs i < j in the list's order (two pinned bodies skipped); per pair the two
// disc trees descended together, the larger disc split first (body 2's when equal), children
// in order; a contact where two blocks' discs overlap, at the midpoint, its normal from body 1's
// block to body 2's. Solve: projected Gauss–Seidel (Erleben) from zero impulses, the contacts in
// the order found, per contact the normal row then the friction row bounded by ±μ λn, the
// bodies' velocity changes kept beside the velocities; b = J (v + h f/m), the velocity the
// body's own step would give. No warm start, no stabilisation, no restitution.
package comp559.lcp;

import java.util.ArrayList;
import java.util.List;
import javax.vecmath.Point2d;
import javax.vecmath.Vector2d;
import mintools.parameters.BooleanParameter;
import mintools.parameters.DoubleParameter;
import mintools.parameters.IntParameter;

public class CollisionProcessor {
    private List<RigidBody> bodies;
    public ArrayList<Contact> contacts = new ArrayList<Contact>();

    public CollisionProcessor(List<RigidBody> bodies) {
        this.bodies = bodies;
    }

    public void processCollisions(double dt) {
        contacts.clear();
        Contact.nextContactIndex = 0;
        for (RigidBody b1 : bodies) {
            for (RigidBody b2 : bodies) {
                if (b1.index >= b2.index || (b1.pinned && b2.pinned)) {
                    continue;
                }
                narrowPhase(b1, b2);
            }
        }
        if (contacts.isEmpty() || !doLCP.getValue()) {
            return;
        }
        solve(dt);
    }

    private void narrowPhase(RigidBody body1, RigidBody body2) {
        if (!useBVTree.getValue()) {
            for (Block b1 : body1.blocks) {
                for (Block b2 : body2.blocks) {
                    processCollision(body1, b1, body2, b2);
                }
            }
            return;
        }
        body1.root.boundingDisc.updatecW();
        body2.root.boundingDisc.updatecW();
        if (body1.root.boundingDisc.intersects(body2.root.boundingDisc)) {
            descend(body1, body1.root, body2, body2.root);
        }
    }

    private void descend(RigidBody body1, BVNode n1, RigidBody body2, BVNode n2) {
        if (n1.isLeaf() && n2.isLeaf()) {
            processCollision(body1, n1.leafBlock, body2, n2.leafBlock);
        } else if (n2.isLeaf() || (!n1.isLeaf() && n1.boundingDisc.r > n2.boundingDisc.r)) {
            for (BVNode child : new BVNode[] {n1.child1, n1.child2}) {
                child.boundingDisc.updatecW();
                if (child.boundingDisc.intersects(n2.boundingDisc)) {
                    descend(body1, child, body2, n2);
                }
            }
        } else {
            for (BVNode child : new BVNode[] {n2.child1, n2.child2}) {
                child.boundingDisc.updatecW();
                if (n1.boundingDisc.intersects(child.boundingDisc)) {
                    descend(body1, n1, body2, child);
                }
            }
        }
    }

    private final Point2d p1 = new Point2d(), p2 = new Point2d(), point = new Point2d();
    private final Vector2d normal = new Vector2d();

    private void processCollision(RigidBody body1, Block b1, RigidBody body2, Block b2) {
        body1.toWorld(b1.pB, p1);
        body2.toWorld(b2.pB, p2);
        double distance = p1.distance(p2);
        if (distance >= Block.radius * 2) {
            return;
        }
        point.interpolate(p1, p2, 0.5);
        if (Bug.is("normal_sign")) {
            normal.sub(p1, p2);
        } else {
            normal.sub(p2, p1);
        }
        normal.normalize();
        contacts.add(new Contact(body1, body2, point, normal));
        if (!doLCP.getValue()) {
            // The starter's penalty spring, frictionless.
            Vector2d f = new Vector2d();
            f.scale((Block.radius * 2 - distance) * 1000, normal);
            body2.applyContactForceW(point, f);
            f.scale(-1);
            body1.applyContactForceW(point, f);
        }
    }

    private void solve(double dt) {
        int n = contacts.size();
        double mu = friction.getValue();
        double[] dv = new double[3 * bodies.size()];
        double[][] rows = new double[2 * n][];
        double[] b = new double[2 * n], diagonal = new double[2 * n], lambda = new double[2 * n];
        double[][] minv = new double[2 * n][];
        for (Contact c : contacts) {
            double[] m = {c.body1.minv, c.body1.minv, c.body1.jinv, c.body2.minv, c.body2.minv, c.body2.jinv};
            double[] u = {
                c.body1.v.x + dt * c.body1.minv * c.body1.force.x,
                c.body1.v.y + dt * c.body1.minv * c.body1.force.y,
                c.body1.omega + dt * c.body1.jinv * c.body1.torque,
                c.body2.v.x + dt * c.body2.minv * c.body2.force.x,
                c.body2.v.y + dt * c.body2.minv * c.body2.force.y,
                c.body2.omega + dt * c.body2.jinv * c.body2.torque,
            };
            rows[2 * c.index] = c.jacobianNormal;
            rows[2 * c.index + 1] = c.jacobianTangent;
            for (int r = 2 * c.index; r < 2 * c.index + 2; r++) {
                minv[r] = m;
                for (int k = 0; k < 6; k++) {
                    b[r] += rows[r][k] * u[k];
                    diagonal[r] += rows[r][k] * rows[r][k] * m[k];
                }
            }
        }
        for (int sweep = 0; sweep < iterations.getValue(); sweep++) {
            for (Contact c : contacts) {
                for (int r = 2 * c.index; r < 2 * c.index + 2; r++) {
                    if (diagonal[r] <= 0) {
                        continue;
                    }
                    double w = b[r];
                    for (int k = 0; k < 3; k++) {
                        w += rows[r][k] * dv[3 * c.body1.index + k] + rows[r][k + 3] * dv[3 * c.body2.index + k];
                    }
                    double next = lambda[r] - w / diagonal[r];
                    if (r % 2 == 0) {
                        next = Math.max(0, next);
                    } else {
                        double bound = Bug.is("friction_bound") ? mu : mu * lambda[r - 1];
                        next = Math.max(-bound, Math.min(bound, next));
                    }
                    double delta = next - lambda[r];
                    lambda[r] = next;
                    for (int k = 0; k < 3; k++) {
                        dv[3 * c.body1.index + k] += minv[r][k] * rows[r][k] * delta;
                        dv[3 * c.body2.index + k] += minv[r][k + 3] * rows[r][k + 3] * delta;
                    }
                }
            }
        }
        for (RigidBody body : bodies) {
            body.v.x += dv[3 * body.index];
            body.v.y += dv[3 * body.index + 1];
            body.omega += dv[3 * body.index + 2];
        }
    }

    public void reset() {
        contacts.clear();
        Contact.nextContactIndex = 0;
    }

    public DoubleParameter restitution = new DoubleParameter("restitution (bounce)", 0, 0, 1);
    public DoubleParameter friction = new DoubleParameter("Coulomb friction", 0.33, 0, 2);
    public IntParameter iterations = new IntParameter("iterations for GS solve", 10, 1, 500);
    private BooleanParameter doLCP = new BooleanParameter("do LCP solve", false);
    private BooleanParameter useBVTree = new BooleanParameter("use BVTree", false);
}
