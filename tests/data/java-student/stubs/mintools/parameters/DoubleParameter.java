// Test stub of the starter's mintools.jar.
package mintools.parameters;

public class DoubleParameter extends BoundedParameter<Double> {
    public DoubleParameter(String name, double defaultValue, double minimum, double maximum) {
        super(name, defaultValue, minimum, maximum);
    }

    public void setValue(double value) {
        setValue(Double.valueOf(value));
    }
}
