"""Typed errors of symgen. Every error names the element of the scene it is about."""


class SymgenError(Exception):
    """Base class of every error symgen raises on purpose."""


class SceneError(SymgenError):
    """A scene is malformed: unknown name, bad value, impossible physics.

    ``element`` names the offending body/joint/frame/constraint (e.g. ``"joint 'elbow'"``).
    """

    def __init__(self, element: str, message: str):
        self.element = element
        self.message = message
        super().__init__(f"{element}: {message}")


class TopologyError(SceneError):
    """The joints do not form a tree rooted at the world, or a loop has no closure."""


class ConstraintError(SceneError):
    """Constraints are redundant, too many, or inconsistent with the task-space choice."""


class SingularConfigurationError(SymgenError):
    """A matrix that must be invertible is singular (or nearly so) at a configuration.

    ``condition`` is the 2-norm condition number estimate (``inf`` for exact singularity).
    """

    def __init__(self, what: str, condition: float, hint: str = ""):
        self.what = what
        self.condition = condition
        text = f"{what} is singular (condition number {condition:.3g})"
        super().__init__(text + (f"; {hint}" if hint else ""))


class StateError(SymgenError):
    """A configuration or velocity handed to a model is missing an entry or has the wrong size."""


class NonFiniteResultError(SymgenError):
    """A model function's result holds NaN or infinity (an input near overflow): named output."""


class SymbolicTooLargeError(SymgenError):
    """A symbolic operation was refused because it would not finish in reasonable time."""


class CodegenError(SymgenError):
    """A scene asks the code generator for something it cannot emit (named in the message)."""


class InertiaWarning(UserWarning):
    """A body's rotational inertia is not quite one of a rigid body (within the tolerance of
    :data:`symgen.scene.checks.INERTIA_TOLERANCE`: accepted as rounding), or was repaired."""


class FixedBaseWarning(UserWarning):
    """A robot whose root looks like a free body (a legged robot, a humanoid, a mobile base) is
    loaded welded to the world: a fixed base. Also in ``scene.notes``."""
