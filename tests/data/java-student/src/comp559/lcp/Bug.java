// The tests' student-like 2D simulator (rigidref's tests/suite/blocks2d/java_student.rs),
// written for rigidref from the assignment's equations in the Java starter's layout and
// conventions: package comp559.lcp, package-private fields, private switches that default to
// the starter's penalty springs and all-pairs test. The typical mistakes are switches, read
// from the system property student.bug, so that one compiled program is every variant.
package comp559.lcp;

final class Bug {
    /** The variant: correct, normal_sign, rigidref_inertia, friction_bound, jacobian_entry. */
    static final String NAME = System.getProperty("student.bug", "correct");

    static {
        switch (NAME) {
            case "correct":
            case "normal_sign":
            case "rigidref_inertia":
            case "friction_bound":
            case "jacobian_entry":
                break;
            default:
                throw new IllegalArgumentException("student.bug: no variant " + NAME);
        }
    }

    /** Whether the variant is `name`. */
    static boolean is(String name) {
        return NAME.equals(name);
    }

    private Bug() {
    }
}
