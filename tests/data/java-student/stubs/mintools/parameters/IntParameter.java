// Test stub of the starter's mintools.jar.
package mintools.parameters;

public class IntParameter extends BoundedParameter<Integer> {
    public IntParameter(String name, int defaultValue, int minimum, int maximum) {
        super(name, defaultValue, minimum, maximum);
    }
}
