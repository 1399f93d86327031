// The tests' student-like simulator: bodies from an image, as the starter's reader makes them
// (see Bug.java): a sweep column by column, each body grown breadth first from its first pixel,
// colours as floats, a block on the boundary when on the image's edge or next to a white pixel
// at an offset (i, j) with i != j.
package comp559.lcp;

import java.awt.image.BufferedImage;
import java.io.File;
import java.util.ArrayDeque;
import java.util.ArrayList;
import javax.imageio.ImageIO;
import javax.vecmath.Color3f;

public class ImageBlocker {
    private int[] argb;
    private boolean[][] visited;
    int width;
    int height;
    private final float epsilon;

    /** The bodies found, in the order found. */
    public ArrayList<RigidBody> bodies = new ArrayList<RigidBody>();

    public ImageBlocker(String filename, float epsilon) {
        this.epsilon = epsilon;
        try {
            BufferedImage img = ImageIO.read(new File(filename));
            width = img.getWidth();
            height = img.getHeight();
            argb = img.getRGB(0, 0, width, height, null, 0, width);
        } catch (Exception e) {
            System.err.println("cannot read " + filename + ": " + e);
            return;
        }
        visited = new boolean[width][height];
        for (int x = 0; x < width; x++) {
            for (int y = 0; y < height; y++) {
                if (visited[x][y]) {
                    continue;
                }
                visited[x][y] = true;
                if (white(x, y)) {
                    continue;
                }
                ArrayList<Block> blocks = new ArrayList<Block>();
                ArrayList<Block> boundary = new ArrayList<Block>();
                grow(x, y, blocks, boundary);
                bodies.add(new RigidBody(blocks, boundary));
            }
        }
    }

    private void grow(int x0, int y0, ArrayList<Block> blocks, ArrayList<Block> boundary) {
        ArrayDeque<int[]> queue = new ArrayDeque<int[]>();
        queue.add(new int[] {x0, y0});
        while (!queue.isEmpty()) {
            int[] p = queue.poll();
            int x = p[0], y = p[1];
            if (white(x, y)) {
                continue;
            }
            Block b = new Block(y, x, colour(x, y));
            blocks.add(b);
            if (onBoundary(x, y)) {
                boundary.add(b);
            }
            for (int i = -1; i <= 1; i++) {
                for (int j = -1; j <= 1; j++) {
                    int nx = x + i, ny = y + j;
                    if (nx >= 0 && nx < width && ny >= 0 && ny < height && !visited[nx][ny]) {
                        visited[nx][ny] = true;
                        queue.add(new int[] {nx, ny});
                    }
                }
            }
        }
    }

    private boolean onBoundary(int x, int y) {
        if (x == 0 || y == 0 || x == width - 1 || y == height - 1) {
            return true;
        }
        for (int i = -1; i <= 1; i++) {
            for (int j = -1; j <= 1; j++) {
                if (i != j && white(x + i, y + j)) {
                    return true;
                }
            }
        }
        return false;
    }

    private Color3f colour(int x, int y) {
        int p = argb[y * width + x];
        return new Color3f(((p >> 16) & 0xff) / 255.0f, ((p >> 8) & 0xff) / 255.0f, (p & 0xff) / 255.0f);
    }

    private boolean white(int x, int y) {
        return colour(x, y).epsilonEquals(new Color3f(1, 1, 1), epsilon);
    }
}
