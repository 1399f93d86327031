// Test stub of vecmath.jar (the part the tests' student-like simulator uses), written for
// rigidref's tests with the arithmetic of the real library's methods.
package javax.vecmath;

public abstract class Tuple2d {
    public double x;
    public double y;

    public Tuple2d() {
    }

    public Tuple2d(double x, double y) {
        this.x = x;
        this.y = y;
    }

    public final void set(double x, double y) {
        this.x = x;
        this.y = y;
    }

    public final void set(Tuple2d t) {
        x = t.x;
        y = t.y;
    }

    public final void add(Tuple2d t) {
        x += t.x;
        y += t.y;
    }

    public final void sub(Tuple2d a, Tuple2d b) {
        x = a.x - b.x;
        y = a.y - b.y;
    }

    public final void scale(double s) {
        x *= s;
        y *= s;
    }

    public final void scale(double s, Tuple2d t) {
        x = s * t.x;
        y = s * t.y;
    }

    public final void interpolate(Tuple2d a, Tuple2d b, double alpha) {
        x = (1 - alpha) * a.x + alpha * b.x;
        y = (1 - alpha) * a.y + alpha * b.y;
    }
}
