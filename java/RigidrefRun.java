// RigidrefRun: runs a student's 2D image-block simulator, written on the Java starter of the
// assignment (package comp559.lcp: RigidBodySystem, CollisionProcessor, RigidBody, Contact,
// ImageBlocker), without a window and without editing the student's files, and writes its
// trace and its first contact problem with RigidrefTrace for `rigidref compare`,
// `rigidref compare-problem` and `rigidref grade`. java/README.md gives the commands.
//
// It is compiled beside the student's files, in their package (so that it reads the starter's
// package-private fields: RigidBody.minv, jinv, massLinear, massAngular, blocks; Contact.body1,
// body2, normal, contactW; Block.pB), with a copy of RigidrefTrace.java given the same package
// line. It does what the starter's LCPApp does for a loaded image, minus the drawing:
//
//   1. RigidBodySystem.clear() (RigidBody.nextIndex back to 0: the bodies' indices are their
//      places in the list, which the student's arrays rely on), a MouseSpringForce when the
//      system has none (advanceTime calls it), then new ImageBlocker(IMAGE, white epsilon)
//      and its bodies added in its order (the starter numbers them column by column);
//   2. every mintools Parameter field of the system and of its collision processor listed on
//      stderr; the collision processor's `doLCP` and `useBVTree` switched on (the starter
//      ships them off: penalty springs and the all-pairs block test) through reflection, as
//      they are private; then each --set FIELD=VALUE;
//   3. per frame, `substeps` calls of RigidBodySystem.advanceTime(step / substeps), as LCPApp's
//      display loop makes them, and one trace record after them (t = frame × step): one record
//      per frame, never one per body or per substep;
//   4. at the first advanceTime call whose collision processor lists contacts, the contact
//      problem that call solved: the bodies' inverse masses (minv, jinv: 0 when pinned) and
//      velocities at the start of the call plus the call's gravity (v + h g: the starter adds
//      gravity to the force accumulator, and the solve works on the velocity it would give;
//      it never stores that velocity), each contact's bodies, point and normal as found at the
//      start of the call, and the Jacobian rows at the centres of mass of that moment
//      (RigidrefTrace.jacobianRows), or with --jacobian NORMAL,TANGENT the student's own rows
//      from those two double[6] fields of Contact ([vx1, vy1, ω1, vx2, vy2, ω2]). The
//      starter's Contact normal points from body 1 towards body 2; rigidref's from body 2 into
//      body 1, so the normal is written negated, with the bodies in the same order: the same
//      constraint rows (a student's rows for body 2's velocity relative to body 1's along n and
//      t = (−n_y, n_x) are exactly rigidref's for −n), not a flipped problem.
//
// Usage: java -cp build:jars/* comp559.lcp.RigidrefRun IMAGE.png [--time T] [--out FILE]
//          [--problem FILE | --no-problem] [--jacobian NORMAL,TANGENT] [--step H]
//          [--substeps N] [--white EPS] [--set FIELD=VALUE]...
// Exit status 0 when the trace is written; 1 when the student's code fails or its state is not
// finite (the trace so far is kept); 2 for a bad command line.

package comp559.lcp;

import java.io.IOException;
import java.lang.reflect.Constructor;
import java.lang.reflect.Field;
import java.lang.reflect.Modifier;
import java.nio.file.Paths;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;

import mintools.parameters.Parameter;

public final class RigidrefRun {
    /** A bad command line (exit status 2), told apart from anything the student's code throws. */
    static final class Usage extends RuntimeException {
        Usage(String message) {
            super(message);
        }
    }

    private String image;
    private double time = 5;
    private String out;
    private String problem;
    private boolean writeProblem = true;
    private String[] jacobian;
    private double step = 0.05;
    private int substeps = 1;
    private double white = 0.05;
    private final Map<String, String> sets = new LinkedHashMap<>();

    public static void main(String[] args) {
        RigidrefRun run = new RigidrefRun();
        try {
            run.parse(args);
        } catch (Usage e) {
            System.err.println("rigidref-run: " + e.getMessage());
            System.err.println("usage: java -cp build:jars/* comp559.lcp.RigidrefRun IMAGE.png [--time T]"
                    + " [--out FILE] [--problem FILE | --no-problem] [--jacobian NORMAL,TANGENT]"
                    + " [--step H] [--substeps N]"
                    + " [--white EPS] [--set FIELD=VALUE]...");
            System.exit(2);
        }
        try {
            run.run();
        } catch (Usage e) {
            System.err.println("rigidref-run: " + e.getMessage());
            System.exit(2);
        } catch (Exception e) {
            System.err.println("rigidref-run: " + run.image + ": the run failed: " + e);
            e.printStackTrace();
            System.exit(1);
        }
    }

    private void parse(String[] args) {
        for (int k = 0; k < args.length; k++) {
            String a = args[k];
            if (!a.startsWith("--")) {
                if (image != null) {
                    throw new Usage("one image only, got " + image + " and " + a);
                }
                image = a;
                continue;
            }
            if (a.equals("--no-problem")) {
                writeProblem = false;
                continue;
            }
            if (k + 1 >= args.length) {
                throw new Usage(a + " needs a value");
            }
            String v = args[++k];
            switch (a) {
                case "--time": time = positive(a, v); break;
                case "--out": out = v; break;
                case "--problem": problem = v; break;
                case "--jacobian":
                    jacobian = v.split(",");
                    if (jacobian.length != 2) {
                        throw new Usage("--jacobian takes the two fields of Contact holding"
                                + " the normal and the tangent row, NORMAL,TANGENT; got " + v);
                    }
                    break;
                case "--step": step = positive(a, v); break;
                case "--substeps":
                    try {
                        substeps = Integer.parseInt(v);
                    } catch (NumberFormatException e) {
                        substeps = 0;
                    }
                    if (substeps < 1) {
                        throw new Usage("--substeps must be a whole number >= 1, got " + v);
                    }
                    break;
                case "--white":
                    try {
                        white = Double.parseDouble(v);
                    } catch (NumberFormatException e) {
                        white = Double.NaN;
                    }
                    if (!(white >= 0 && white < 1)) {
                        throw new Usage("--white must be a number in [0, 1), got " + v);
                    }
                    break;
                case "--set": {
                    int eq = v.indexOf('=');
                    if (eq <= 0) {
                        throw new Usage("--set takes FIELD=VALUE, got " + v);
                    }
                    sets.put(v.substring(0, eq), v.substring(eq + 1));
                    break;
                }
                default: throw new Usage("unknown option " + a);
            }
        }
        if (image == null) {
            throw new Usage("no image given");
        }
        String name = Paths.get(image).getFileName().toString().replaceFirst("\\.[^.]*$", "");
        if (out == null) {
            out = name + ".jsonl";
        }
        if (problem == null) {
            problem = name + ".problem.json";
        }
    }

    private static double positive(String option, String v) {
        double x;
        try {
            x = Double.parseDouble(v);
        } catch (NumberFormatException e) {
            x = Double.NaN;
        }
        if (!(x > 0) || Double.isInfinite(x)) {
            throw new Usage(option + " must be a positive number, got " + v);
        }
        return x;
    }

    private void run() throws Exception {
        if (jacobian != null) {
            for (String name : jacobian) {
                Field f;
                try {
                    f = Contact.class.getDeclaredField(name);
                } catch (NoSuchFieldException e) {
                    throw new Usage("--jacobian: Contact has no field " + name);
                }
                if (f.getType() != double[].class) {
                    throw new Usage("--jacobian: Contact." + name + " is a " + f.getType().getSimpleName()
                            + ", not six numbers (double[6]: body 1's vx, vy, omega, body 2's vx, vy, omega)");
                }
            }
        }
        RigidBodySystem system = new RigidBodySystem();
        system.clear();
        giveMouseSpring(system);
        ImageBlocker blocker = new ImageBlocker(image, (float) white);
        if (blocker.bodies.isEmpty()) {
            throw new Usage(image + ": the starter's ImageBlocker found no bodies in it"
                    + " (a missing or unreadable file prints its error above)");
        }
        system.name = image;
        system.bodies.addAll(blocker.bodies);

        List<Object> owners = List.of(system, system.collisionProcessor);
        Map<String, Field> parameters = parameterFields(owners);
        for (String flag : new String[] {"doLCP", "useBVTree"}) {
            if (parameters.containsKey(flag)) {
                set(parameters, owners, flag, "true");
            } else {
                System.err.println("rigidref-run: warning: the collision processor has no field " + flag
                        + "; whether its contact solve or tree is used cannot be switched");
            }
        }
        for (Map.Entry<String, String> e : sets.entrySet()) {
            set(parameters, owners, e.getKey(), e.getValue());
        }
        for (Map.Entry<String, Field> e : parameters.entrySet()) {
            Field f = e.getValue();
            Parameter<?> p = (Parameter<?>) f.get(owner(owners, f));
            System.err.println("rigidref-run: " + f.getDeclaringClass().getSimpleName() + "." + e.getKey()
                    + " = " + p.getValue() + "  (\"" + p.getName() + "\")");
        }

        double[] g = gravity(parameters, owners);
        int n = system.bodies.size();
        long frames = Math.round(time / step);
        double h = step / substeps;
        String scene = Paths.get(image).getFileName().toString().replaceFirst("\\.[^.]*$", "");
        RigidrefTrace trace = new RigidrefTrace(out, scene, image, step, substeps, g[0], g[1]);
        try {
            for (int i = 0; i < n; i++) {
                RigidBody b = system.bodies.get(i);
                trace.body("body" + i, b.massLinear, b.massAngular, b.pinned, b.blocks.size());
            }
            record(trace, system, 0.0);
            boolean pending = writeProblem;
            for (long frame = 1; frame <= frames; frame++) {
                for (int s = 0; s < substeps; s++) {
                    double[][] before = pending ? state(system) : null;
                    system.advanceTime(h);
                    if (pending && !system.collisionProcessor.contacts.isEmpty()) {
                        writeProblem(system, before, h, g);
                        pending = false;
                    }
                }
                record(trace, system, frame * step);
            }
            if (pending) {
                System.err.println("rigidref-run: no contacts in " + time + " time units: no problem written");
            }
        } finally {
            trace.close();
        }
        System.err.println("rigidref-run: " + n + " bodies, " + frames + " frames of " + step + " ("
                + substeps + " substeps), trace " + out);
    }

    /** The system's MouseSpringForce, made when it has none (the starter's advanceTime calls it). */
    private static void giveMouseSpring(RigidBodySystem system) throws Exception {
        Field f;
        try {
            f = RigidBodySystem.class.getDeclaredField("mouseSpring");
        } catch (NoSuchFieldException e) {
            return;
        }
        f.setAccessible(true);
        if (f.get(system) != null) {
            return;
        }
        for (Constructor<?> c : f.getType().getDeclaredConstructors()) {
            Class<?>[] types = c.getParameterTypes();
            if (types.length == 1) {
                c.setAccessible(true);
                f.set(system, c.newInstance(types[0].getDeclaredConstructor().newInstance()));
                return;
            }
        }
        throw new IllegalStateException("cannot make a " + f.getType().getSimpleName()
                + " for RigidBodySystem.mouseSpring (no one-argument constructor)");
    }

    /** The mintools Parameter fields of the owners, by Java field name (the first owner's first). */
    private static Map<String, Field> parameterFields(List<Object> owners) {
        Map<String, Field> fields = new LinkedHashMap<>();
        for (Object o : owners) {
            for (Field f : o.getClass().getDeclaredFields()) {
                if (!Modifier.isStatic(f.getModifiers()) && Parameter.class.isAssignableFrom(f.getType())) {
                    f.setAccessible(true);
                    fields.putIfAbsent(f.getName(), f);
                }
            }
        }
        return fields;
    }

    private static Object owner(List<Object> owners, Field f) {
        for (Object o : owners) {
            if (f.getDeclaringClass().isInstance(o)) {
                return o;
            }
        }
        throw new IllegalStateException("no owner of " + f);
    }

    /** Sets parameter field `name` from text, in the type of its current value; refuses a clamp. */
    @SuppressWarnings("unchecked")
    private static void set(Map<String, Field> parameters, List<Object> owners, String name, String text)
            throws IllegalAccessException {
        Field f = parameters.get(name);
        if (f == null) {
            throw new Usage("--set " + name + ": no such parameter; the parameters are "
                    + String.join(", ", parameters.keySet()));
        }
        Parameter<Object> p = (Parameter<Object>) f.get(owner(owners, f));
        Object now = p.getValue();
        Object value;
        try {
            if (now instanceof Boolean) {
                if (!text.equals("true") && !text.equals("false")) {
                    throw new NumberFormatException();
                }
                value = Boolean.valueOf(text);
            } else if (now instanceof Integer) {
                value = Integer.valueOf(text);
            } else if (now instanceof Double) {
                value = Double.valueOf(text);
            } else {
                throw new Usage("--set " + name + ": a " + now.getClass().getSimpleName()
                        + " parameter cannot be set from the command line");
            }
        } catch (NumberFormatException e) {
            throw new Usage("--set " + name + "=" + text + ": not a "
                    + now.getClass().getSimpleName().toLowerCase());
        }
        p.setValue(value);
        if (!p.getValue().equals(value)) {
            throw new Usage("--set " + name + "=" + text + ": the parameter keeps "
                    + p.getValue() + " (outside its range)");
        }
    }

    /** Gravity (gx, gy) as the starter's RigidBodySystem applies it: amount (cos a, sin a). */
    private static double[] gravity(Map<String, Field> parameters, List<Object> owners)
            throws IllegalAccessException {
        Object on = value(parameters, owners, "useGravity");
        Object amount = value(parameters, owners, "gravityAmount");
        Object angle = value(parameters, owners, "gravityAngle");
        if (on == null || amount == null || angle == null) {
            throw new IllegalStateException("RigidBodySystem has no useGravity, gravityAmount and gravityAngle"
                    + " parameters: the trace's gravity cannot be stated");
        }
        if (!(Boolean) on) {
            return new double[] {0, 0};
        }
        double theta = (Double) angle / 180.0 * Math.PI;
        double g = (Double) amount;
        return new double[] {Math.cos(theta) * g, Math.sin(theta) * g};
    }

    private static Object value(Map<String, Field> parameters, List<Object> owners, String name)
            throws IllegalAccessException {
        Field f = parameters.get(name);
        return f == null ? null : ((Parameter<?>) f.get(owner(owners, f))).getValue();
    }

    /** Every body's (x, y, theta, vx, vy, omega), in the system's order. */
    private static double[][] state(RigidBodySystem system) {
        int n = system.bodies.size();
        double[][] s = new double[6][n];
        for (int i = 0; i < n; i++) {
            RigidBody b = system.bodies.get(i);
            s[0][i] = b.x.x;
            s[1][i] = b.x.y;
            s[2][i] = b.theta;
            s[3][i] = b.v.x;
            s[4][i] = b.v.y;
            s[5][i] = b.omega;
        }
        return s;
    }

    private static void record(RigidrefTrace trace, RigidBodySystem system, double t) throws IOException {
        double[][] s = state(system);
        try {
            trace.record(t, s[0], s[1], s[2], s[3], s[4], s[5]);
        } catch (IllegalArgumentException e) {
            throw new IllegalStateException("at t = " + t + " the simulator's state is " + e.getMessage()
                    + "; the trace so far is kept", e);
        }
    }

    /** The contact problem of the advanceTime call that started from state `before` (class notes). */
    private void writeProblem(RigidBodySystem system, double[][] before, double h, double[] g)
            throws IOException {
        RigidrefTrace.Problem p = new RigidrefTrace.Problem();
        List<RigidBody> bodies = system.bodies;
        for (int i = 0; i < bodies.size(); i++) {
            RigidBody b = bodies.get(i);
            double kick = b.pinned ? 0 : h;
            p.body(b.pinned ? 0 : b.minv, b.pinned ? 0 : b.jinv, before[3][i] + kick * g[0],
                    before[4][i] + kick * g[1], before[5][i]);
        }
        double mu = system.collisionProcessor.friction.getValue();
        List<Contact> contacts = new ArrayList<>(system.collisionProcessor.contacts);
        for (Contact c : contacts) {
            int i = bodies.indexOf(c.body1), j = bodies.indexOf(c.body2);
            double nx = -c.normal.x, ny = -c.normal.y; // rigidref's: from body 2 into body 1
            double[][] rows = jacobian == null
                    ? RigidrefTrace.jacobianRows(c.contactW.x, c.contactW.y, nx, ny,
                            before[0][i], before[1][i], before[0][j], before[1][j])
                    : new double[][] {row(c, jacobian[0]), row(c, jacobian[1])};
            p.contact(i, j, c.contactW.x, c.contactW.y, nx, ny, depth(c, before, i), mu, rows);
        }
        p.write(problem);
        System.err.println("rigidref-run: first contact problem (" + contacts.size() + " contacts) "
                + problem);
    }

    /** The student's Jacobian row in field `name` of the contact: six numbers. */
    private static double[] row(Contact c, String name) {
        Object value;
        try {
            Field f = Contact.class.getDeclaredField(name);
            f.setAccessible(true);
            value = f.get(c);
        } catch (NoSuchFieldException | IllegalAccessException e) {
            throw new Usage("--jacobian: Contact has no field " + name);
        }
        if (!(value instanceof double[]) || ((double[]) value).length != 6) {
            throw new Usage("--jacobian: Contact." + name + " is not six numbers"
                    + " (double[6]: body 1's vx, vy, omega, body 2's vx, vy, omega)");
        }
        return ((double[]) value).clone();
    }

    /**
     * The overlap 2r − |p₁ − p₂| of a contact, from body 1's block whose centre (at the start of
     * the call) lies on the contact's normal line through its point, on body 1's side (the
     * starter's Contact keeps no blocks); 0 when none does.
     */
    private static double depth(Contact c, double[][] before, int i) {
        double cos = Math.cos(before[2][i]), sin = Math.sin(before[2][i]);
        double best = Double.POSITIVE_INFINITY;
        for (Block k : c.body1.blocks) {
            double wx = before[0][i] + cos * k.pB.x - sin * k.pB.y;
            double wy = before[1][i] + sin * k.pB.x + cos * k.pB.y;
            double dx = c.contactW.x - wx, dy = c.contactW.y - wy;
            double along = dx * c.normal.x + dy * c.normal.y;
            double across = Math.abs(dx * c.normal.y - dy * c.normal.x);
            if (along >= 0 && across < 1e-9 && along < best) {
                best = along;
            }
        }
        return best == Double.POSITIVE_INFINITY ? 0 : 2 * Block.radius - 2 * best;
    }
}
