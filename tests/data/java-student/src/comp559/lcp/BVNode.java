// The tests' student-like simulator: the bounding-disc tree as the starter builds it (see
// Bug.java): a node's blocks split at the middle of their bounding box, across y when it is
// taller than wide and across x otherwise, those below the middle the first child.
package comp559.lcp;

import java.util.ArrayList;
import java.util.List;
import javax.vecmath.Point2d;

public class BVNode {
    Disc boundingDisc;
    BVNode child1;
    BVNode child2;
    Block leafBlock;

    public BVNode(List<Block> blocks, RigidBody body) {
        boundingDisc = new Disc(blocks, body);
        if (blocks.size() == 1) {
            leafBlock = blocks.get(0);
            return;
        }
        Point2d max = new Point2d(blocks.get(0).pB), min = new Point2d(blocks.get(0).pB);
        for (Block b : blocks) {
            max.set(Math.max(max.x, b.pB.x), Math.max(max.y, b.pB.y));
            min.set(Math.min(min.x, b.pB.x), Math.min(min.y, b.pB.y));
        }
        Point2d middle = new Point2d();
        middle.interpolate(max, min, 0.5);
        boolean acrossY = max.y - min.y > max.x - min.x;
        ArrayList<Block> first = new ArrayList<Block>(), second = new ArrayList<Block>();
        for (Block b : blocks) {
            boolean below = acrossY ? b.pB.y < middle.y : b.pB.x < middle.x;
            (below ? first : second).add(b);
        }
        child1 = new BVNode(first, body);
        child2 = new BVNode(second, body);
    }

    public boolean isLeaf() {
        return leafBlock != null;
    }
}
