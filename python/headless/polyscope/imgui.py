"""A stand-in for polyscope.imgui (see polyscope/__init__.py): the "Run" checkbox reads as
ticked, every other widget returns its value unchanged, buttons are not pressed."""


def Checkbox(label, value, *args, **kwargs):
    return False, True if label == "Run" else value


def Button(*args, **kwargs):
    return False


def TreeNode(*args, **kwargs):
    return False


def _unchanged(label, value, *args, **kwargs):
    return False, value


SliderFloat = SliderInt = InputInt = InputFloat = InputFloat3 = DragFloat = DragInt = _unchanged


def __getattr__(name):
    """Every other widget (text, separators, tree ends): does nothing."""
    if name.startswith("__"):
        raise AttributeError(name)
    return lambda *args, **kwargs: None
