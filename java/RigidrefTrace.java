// RigidrefTrace: writes a 2D simulation's states as a rigidref trace (docs/trace-format.md,
// "2D traces"), so that `rigidref compare` can check it against the reference, and its contact
// problems (RigidrefTrace.Problem; docs/contact-problem-format.md) for `rigidref compare-problem`
// and `rigidref grade`. One file, no
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

    /**
     * The Jacobian rows of a 2D contact as rigidref defines them (docs/blocks2d.md, "Contact
     * problem"): at point (px, py) with unit normal (nx, ny) pointing from body 2 into body 1,
     * tangent t = (-ny, nx), body 1's centre of mass (x1, y1) and body 2's (x2, y2). Returns
     * {{n row: body 1 (nx, ny, r1 x n), body 2 -(nx, ny, r2 x n)}, {t row: likewise}}, each row
     * six numbers [J1 | J2], r = p - centre, a x b = a_x b_y - a_y b_x.
     */
    public static double[][] jacobianRows(double px, double py, double nx, double ny,
            double x1, double y1, double x2, double y2) {
        double tx = -ny, ty = nx;
        double r1x = px - x1, r1y = py - y1, r2x = px - x2, r2y = py - y2;
        return new double[][] {
            {nx, ny, r1x * ny - r1y * nx, -nx, -ny, -(r2x * ny - r2y * nx)},
            {tx, ty, r1x * ty - r1y * tx, -tx, -ty, -(r2x * ty - r2y * tx)},
        };
    }

    /**
     * One 2D contact problem (docs/contact-problem-format.md) as the simulator assembled it, for
     * `rigidref compare-problem` and `rigidref grade` (a scene's NAME.problem.json is its first
     * contact problem). Declare every body in the trace's order, then every contact; optionally
     * the impulses the solver found; then write. Box friction (each friction impulse within
     * +-mu lambda_n), as the starter's projected Gauss-Seidel.
     */
    public static final class Problem {
        private final List<double[]> bodies = new ArrayList<>(); // 1/m, 1/I, vx, vy, omega
        private final List<int[]> pairs = new ArrayList<>();
        private final List<double[]> contacts = new ArrayList<>(); // p, n, depth, mu, J (12)
        private double[][] lambda;
        private int iterations;

        /**
         * Declares the next body: inverse mass and inverse inertia (0 for a pinned body) and its
         * velocity before the contact impulses (after this step's gravity).
         */
        public void body(double inverseMass, double inverseInertia, double vx, double vy,
                double omega) {
            bodies.add(new double[] {inverseMass, inverseInertia, vx, vy, omega});
        }

        /**
         * Declares the next contact between bodies i and j (indices as declared): point, unit
         * normal (from body j into body i), penetration depth, friction coefficient, and the
         * Jacobian rows (see jacobianRows). Its right-hand side is b = J u.
         */
        public void contact(int i, int j, double px, double py, double nx, double ny,
                double depth, double mu, double[][] jacobian) {
            if (i < 0 || j < 0 || i >= bodies.size() || j >= bodies.size()) {
                throw new IllegalArgumentException("contact bodies " + i + ", " + j
                        + ": declare the bodies first (there are " + bodies.size() + ")");
            }
            if (jacobian.length != 2 || jacobian[0].length != 6 || jacobian[1].length != 6) {
                throw new IllegalArgumentException("the Jacobian is 2 rows (n, t) of 6 numbers");
            }
            double[] c = new double[18];
            c[0] = px; c[1] = py; c[2] = nx; c[3] = ny; c[4] = depth; c[5] = mu;
            System.arraycopy(jacobian[0], 0, c, 6, 6);
            System.arraycopy(jacobian[1], 0, c, 12, 6);
            pairs.add(new int[] {i, j});
            contacts.add(c);
        }

        /**
         * The solver's impulses, one {lambda_n, lambda_t} per contact in declaration order,
         * after `iterations` sweeps. The file then also holds the residual (docs/contact.md,
         * "Residual"), computed here from the problem.
         */
        public void solution(double[][] lambda, int iterations) {
            if (lambda.length != contacts.size()) {
                throw new IllegalArgumentException("one impulse pair per contact: "
                        + contacts.size() + " contacts, " + lambda.length + " given");
            }
            this.lambda = lambda;
            this.iterations = iterations;
        }

        private double[] velocity(int body) {
            double[] b = bodies.get(body);
            return new double[] {b[2], b[3], b[4]};
        }

        /** Row r of contact k times the velocities u (u[body] = {vx, vy, omega}). */
        private double rowTimes(int k, int r, double[][] u) {
            double[] c = contacts.get(k);
            int[] pair = pairs.get(k);
            double w = 0;
            for (int d = 0; d < 3; d++) {
                w += c[6 + 6 * r + d] * u[pair[0]][d] + c[6 + 6 * r + 3 + d] * u[pair[1]][d];
            }
            return w;
        }

        /** The largest natural-map term over all rows (docs/contact.md, "Residual"). */
        private double residual() {
            int n = bodies.size();
            double[][] u = new double[n][];
            double[][] after = new double[n][];
            for (int i = 0; i < n; i++) {
                u[i] = velocity(i);
                after[i] = velocity(i);
            }
            double[][] diagonal = new double[contacts.size()][2];
            for (int k = 0; k < contacts.size(); k++) {
                double[] c = contacts.get(k);
                int[] pair = pairs.get(k);
                for (int r = 0; r < 2; r++) {
                    for (int side = 0; side < 2; side++) {
                        double[] m = bodies.get(pair[side]);
                        double[] inverse = {m[0], m[0], m[1]};
                        for (int d = 0; d < 3; d++) {
                            double j = c[6 + 6 * r + 3 * side + d];
                            after[pair[side]][d] += inverse[d] * j * lambda[k][r];
                            diagonal[k][r] += j * j * inverse[d];
                        }
                    }
                }
            }
            double worst = 0;
            for (int k = 0; k < contacts.size(); k++) {
                double mu = contacts.get(k)[5];
                double ln = lambda[k][0], lt = lambda[k][1];
                double wn = rowTimes(k, 0, after), wt = rowTimes(k, 1, after);
                double an = diagonal[k][0], at = diagonal[k][1];
                double bound = mu * Math.max(ln, 0);
                double normal = an > 0 ? Math.abs(Math.min(an * ln, wn)) : Math.abs(Math.min(ln, wn));
                double friction = at > 0
                        ? at * Math.abs(lt - Math.max(-bound, Math.min(bound, lt - wt / at)))
                        : Math.max(Math.abs(lt) - bound, 0);
                worst = Math.max(worst, Math.max(normal, friction));
            }
            return worst;
        }

        /** Writes the problem to `path` (JSON, docs/contact-problem-format.md). */
        public void write(String path) throws IOException {
            int n = bodies.size();
            double[][] u = new double[n][];
            for (int i = 0; i < n; i++) {
                u[i] = velocity(i);
            }
            StringBuilder s = new StringBuilder();
            s.append("{\"format\":\"rigidref-contact-problem\",\"version\":1,")
                    .append("\"dof_per_body\":3,\"rows_per_contact\":2,\"friction\":\"box\",\"bodies\":[");
            for (int i = 0; i < n; i++) {
                double[] b = bodies.get(i);
                s.append(i > 0 ? "," : "").append("{\"inverse_mass\":[[").append(num(b[0]))
                        .append(",0.0,0.0],[0.0,").append(num(b[0])).append(",0.0],[0.0,0.0,")
                        .append(num(b[1])).append("]],\"velocity\":[").append(num(b[2]))
                        .append(',').append(num(b[3])).append(',').append(num(b[4])).append("]}");
            }
            s.append("],\"contacts\":[");
            for (int k = 0; k < contacts.size(); k++) {
                double[] c = contacts.get(k);
                int[] pair = pairs.get(k);
                s.append(k > 0 ? "," : "").append("{\"bodies\":[").append(pair[0]).append(',')
                        .append(pair[1]).append("],\"jacobian\":[");
                for (int side = 0; side < 2; side++) {
                    s.append(side > 0 ? "," : "").append('[');
                    for (int r = 0; r < 2; r++) {
                        s.append(r > 0 ? "," : "").append('[');
                        for (int d = 0; d < 3; d++) {
                            s.append(d > 0 ? "," : "").append(num(c[6 + 6 * r + 3 * side + d]));
                        }
                        s.append(']');
                    }
                    s.append(']');
                }
                s.append("],\"b\":[").append(num(rowTimes(k, 0, u))).append(',')
                        .append(num(rowTimes(k, 1, u))).append("],\"mu\":").append(num(c[5]))
                        .append(",\"compliance\":0.0,\"lambda0\":[0.0,0.0],\"geometry\":{\"p\":[")
                        .append(num(c[0])).append(',').append(num(c[1])).append("],\"n\":[")
                        .append(num(c[2])).append(',').append(num(c[3])).append("],\"depth\":")
                        .append(num(c[4])).append("}}");
            }
            s.append(']');
            if (lambda != null) {
                s.append(",\"solution\":{\"solver\":\"java\",\"lambda\":[");
                for (int k = 0; k < lambda.length; k++) {
                    s.append(k > 0 ? "," : "").append('[').append(num(lambda[k][0])).append(',')
                            .append(num(lambda[k][1])).append(']');
                }
                s.append("],\"iterations\":").append(iterations).append(",\"residual\":")
                        .append(num(residual())).append('}');
            }
            s.append("}\n");
            Files.write(Paths.get(path), s.toString().getBytes(StandardCharsets.UTF_8));
        }
    }

    @Override
    public void close() throws IOException {
        out.close();
    }
}
