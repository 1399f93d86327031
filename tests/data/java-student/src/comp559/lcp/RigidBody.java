// The tests' student-like simulator: a body of blocks (see Bug.java). Its inertia is the
// starter's (point-mass blocks, a lone block m (1 + 1)/12) or, in the variant
// rigidref_inertia, rigidref's default (each block a unit square).
package comp559.lcp;

import java.util.ArrayList;
import javax.vecmath.Point2d;
import javax.vecmath.Vector2d;

public class RigidBody {
    public int index;
    static public int nextIndex = 0;
    ArrayList<Block> blocks;
    ArrayList<Block> boundaryBlocks;
    BVNode root;
    Vector2d force = new Vector2d();
    double torque;
    double massAngular;
    double massLinear;
    public boolean pinned;
    public Vector2d v = new Vector2d();
    public Point2d x = new Point2d();
    Point2d x0 = new Point2d();
    public double theta;
    public double omega;
    double minv;
    double jinv;

    public RigidBody(ArrayList<Block> blocks, ArrayList<Block> boundaryBlocks) {
        this.blocks = blocks;
        this.boundaryBlocks = boundaryBlocks;
        for (Block b : blocks) {
            double m = b.getColourMass();
            massLinear += m;
            x0.x += b.j * m;
            x0.y += b.i * m;
        }
        x0.scale(1 / massLinear);
        for (Block b : blocks) {
            b.pB.set(b.j - x0.x, b.i - x0.y);
        }
        Point2d zero = new Point2d(0, 0);
        for (Block b : blocks) {
            double r2 = b.pB.distanceSquared(zero);
            massAngular += b.getColourMass() * (Bug.is("rigidref_inertia") ? r2 + 1.0 / 6.0 : r2);
        }
        if (blocks.size() == 1 && !Bug.is("rigidref_inertia")) {
            massAngular = blocks.get(0).getColourMass() * (1 + 1) / 12.0;
        }
        x.set(x0);
        root = new BVNode(boundaryBlocks, this);
        pinned = true;
        for (Block b : blocks) {
            pinned &= b.c.x == b.c.y && b.c.x < b.c.z;
        }
        minv = pinned ? 0 : 1 / massLinear;
        jinv = pinned ? 0 : 1 / massAngular;
        index = nextIndex++;
    }

    /** A body-frame point in the world: x + R(θ) p. */
    void toWorld(Point2d p, Point2d out) {
        double c = Math.cos(theta), s = Math.sin(theta);
        out.set(x.x + (c * p.x - s * p.y), x.y + (s * p.x + c * p.y));
    }

    /** Symplectic Euler: v += h f/m, ω += h τ/I, then x += h v, θ += h ω. */
    public void advanceTime(double dt) {
        if (!pinned) {
            v.x += minv * force.x * dt;
            v.y += minv * force.y * dt;
            omega += jinv * torque * dt;
            x.x += v.x * dt;
            x.y += v.y * dt;
            theta += omega * dt;
        }
        force.set(0, 0);
        torque = 0;
    }

    /** A force at a world point: adds it, and its torque (p − x) × f. */
    public void applyContactForceW(Point2d p, Vector2d f) {
        force.add(f);
        torque += (p.x - x.x) * f.y - (p.y - x.y) * f.x;
    }

    public double getKineticEnergy() {
        return 0.5 * massLinear * v.lengthSquared() + 0.5 * massAngular * omega * omega;
    }

    public void reset() {
        x.set(x0);
        theta = 0;
        v.set(0, 0);
        omega = 0;
    }
}
