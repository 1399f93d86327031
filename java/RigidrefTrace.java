// RigidrefTrace: writes a 2D simulation's states as a rigidref trace (docs/trace-format.md,
// "2D traces"), so that `rigidref compare` can check it against the reference. One file, no
// dependencies, Java 11 or later: copy it next to the starter's sources (default package) and
// call it once per step. java/README.md shows where in the image-block starter.
//
// Units and frame are the 2D system's: one block is one unit of length and (a black block) of
// mass; x is the image column, y the row, y down; angles from +x toward +y. Energies and
// momenta are computed here from what the simulator gives (mass, inertia, state), as rigidref
// computes them: kinetic ½ m |v|² + ½ I ω², potential −m g·x, of the bodies that are not pinned;
// momentum Σ m v and Σ (x × m v + I ω) about the origin.

import java.io.BufferedWriter;
import java.io.IOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Paths;
import java.util.ArrayList;
import java.util.List;
import java.util.Locale;

public final class RigidrefTrace implements AutoCloseable {
    private final BufferedWriter out;
    private final String scene;
    private final String source;
    private final double dt;
    private final int substeps;
    private final double gx;
    private final double gy;
    private final List<double[]> bodies = new ArrayList<>(); // mass, inertia, pinned (1/0), blocks
    private final List<String> names = new ArrayList<>();
    private boolean headerWritten = false;
    private long step = 0;

    /**
     * Opens the trace at `path`. `scene` names the scene (the image's name), `source` the image
     * file; `dt` the step, `substeps` the substeps per step, (gx, gy) gravity (blocks per time
     * unit squared; y down, so falling is +y).
     */
    public RigidrefTrace(String path, String scene, String source, double dt, int substeps,
            double gx, double gy) throws IOException {
        this.out = Files.newBufferedWriter(Paths.get(path), StandardCharsets.UTF_8);
        this.scene = scene;
        this.source = source;
        this.dt = dt;
        this.substeps = substeps;
        this.gx = gx;
        this.gy = gy;
    }

    /** Declares the next body (in the simulator's order), before the first record. */
    public void body(String name, double mass, double inertia, boolean pinned, int blocks) {
        if (headerWritten) {
            throw new IllegalStateException("bodies are declared before the first record");
        }
        names.add(name);
        bodies.add(new double[] {mass, inertia, pinned ? 1 : 0, blocks});
    }

    /**
     * Writes the state after a step: per body (in declaration order) its centre of mass
     * (x[i], y[i]), angle theta[i], velocity (vx[i], vy[i]) and angular velocity omega[i], at
     * time t. The first call should be the initial state (t = 0).
     */
    public void record(double t, double[] x, double[] y, double[] theta, double[] vx,
            double[] vy, double[] omega) throws IOException {
        int n = bodies.size();
        for (double[] a : new double[][] {x, y, theta, vx, vy, omega}) {
            if (a.length != n) {
                throw new IllegalArgumentException(
                        "every array needs " + n + " entries, one per declared body");
            }
        }
        if (!headerWritten) {
            writeHeader();
        }
        StringBuilder s = new StringBuilder();
        s.append("{\"step\":").append(step).append(",\"t\":").append(num(t)).append(",\"bodies\":[");
        double kinetic = 0, potential = 0, px = 0, py = 0, angular = 0;
        for (int i = 0; i < n; i++) {
            if (i > 0) {
                s.append(',');
            }
            s.append("{\"x\":[").append(num(x[i])).append(',').append(num(y[i]))
                    .append("],\"theta\":").append(num(theta[i]))
                    .append(",\"v\":[").append(num(vx[i])).append(',').append(num(vy[i]))
                    .append("],\"omega\":").append(num(omega[i])).append('}');
            double m = bodies.get(i)[0], inertia = bodies.get(i)[1];
            if (bodies.get(i)[2] == 0) {
                kinetic += 0.5 * m * (vx[i] * vx[i] + vy[i] * vy[i]) + 0.5 * inertia * omega[i] * omega[i];
                potential += -m * (gx * x[i] + gy * y[i]);
                px += m * vx[i];
                py += m * vy[i];
                angular += x[i] * (m * vy[i]) - y[i] * (m * vx[i]) + inertia * omega[i];
            }
        }
        s.append("],\"energy\":{\"kinetic\":").append(num(kinetic))
                .append(",\"potential\":").append(num(potential))
                .append(",\"total\":").append(num(kinetic + potential))
                .append("},\"momentum\":{\"linear\":[").append(num(px)).append(',').append(num(py))
                .append("],\"angular\":").append(num(angular))
                .append("},\"contact_count\":0,\"deepest_overlap\":0.0}");
        out.write(s.toString());
        out.write('\n');
        step++;
    }

    private void writeHeader() throws IOException {
        StringBuilder s = new StringBuilder();
        s.append("{\"format\":\"rigidref-trace\",\"version\":2,\"dimension\":2,\"scene\":")
                .append(str(scene)).append(",\"source\":").append(str(source))
                .append(",\"dt\":").append(num(dt)).append(",\"substeps\":").append(substeps)
                .append(",\"gravity\":[").append(num(gx)).append(',').append(num(gy))
                .append("],\"bodies\":[");
        for (int i = 0; i < bodies.size(); i++) {
            double[] b = bodies.get(i);
            if (i > 0) {
                s.append(',');
            }
            s.append("{\"name\":").append(str(names.get(i))).append(",\"mass\":").append(num(b[0]))
                    .append(",\"pinned\":").append(b[2] != 0).append(",\"blocks\":").append((long) b[3])
                    .append('}');
        }
        s.append("]}");
        out.write(s.toString());
        out.write('\n');
        headerWritten = true;
    }

    /** A number as JSON: shortest round-trip decimal; NaN and infinities refused. */
    private static String num(double v) {
        if (Double.isNaN(v) || Double.isInfinite(v)) {
            throw new IllegalArgumentException("not a finite number: " + v);
        }
        return Double.toString(v).replace('E', 'e');
    }

    private static String str(String s) {
        StringBuilder b = new StringBuilder("\"");
        for (char c : s.toCharArray()) {
            if (c == '"' || c == '\\') {
                b.append('\\').append(c);
            } else if (c < 0x20) {
                b.append(String.format(Locale.ROOT, "\\u%04x", (int) c));
            } else {
                b.append(c);
            }
        }
        return b.append('"').toString();
    }

    @Override
    public void close() throws IOException {
        out.close();
    }
}
