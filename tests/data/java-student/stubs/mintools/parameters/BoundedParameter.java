// Test stub of the starter's mintools.jar: a parameter clamped to [minimum, maximum].
package mintools.parameters;

public abstract class BoundedParameter<T extends Comparable<T>> extends Parameter<T> {
    protected final T minimum;
    protected final T maximum;

    public BoundedParameter(String name, T defaultValue, T minimum, T maximum) {
        super(name, defaultValue);
        this.minimum = minimum;
        this.maximum = maximum;
    }

    @Override
    public void setValue(T value) {
        if (value.compareTo(minimum) < 0) {
            value = minimum;
        } else if (value.compareTo(maximum) > 0) {
            value = maximum;
        }
        super.setValue(value);
    }

    public T getMinimum() {
        return minimum;
    }

    public T getMaximum() {
        return maximum;
    }
}
