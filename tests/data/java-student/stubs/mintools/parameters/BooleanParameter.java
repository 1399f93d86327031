// Test stub of the starter's mintools.jar.
package mintools.parameters;

public class BooleanParameter extends Parameter<Boolean> {
    public BooleanParameter(String name, boolean defaultValue) {
        super(name, defaultValue);
    }
}
