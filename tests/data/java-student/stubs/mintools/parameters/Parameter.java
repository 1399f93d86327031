// Test stub of the starter's mintools.jar (its parameter classes only, the API the starter and
// java/RigidrefRun.java use; no user interface). Written for rigidref's tests.
package mintools.parameters;

public abstract class Parameter<T> {
    protected final String name;
    protected T defaultValue;
    protected T value;

    public Parameter(String name, T defaultValue) {
        this.name = name;
        this.defaultValue = defaultValue;
        this.value = defaultValue;
    }

    public void setValue(T value) {
        this.value = value;
    }

    public T getValue() {
        return value;
    }

    public T getDefaultValue() {
        return defaultValue;
    }

    public String getName() {
        return name;
    }
}
