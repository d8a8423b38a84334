"""symgen: symbolic models of general constrained robots.

Implements Zhu, Piedboeuf & Gonthier, *A dynamics formulation of general constrained robots*
(Multibody System Dynamics, 2006): a robot is described by the dynamics of its rigid links and
joints (the extended subsystem space S) tied together by the velocity maps ``T_S`` (eq. 25) and
``[J_m; J_f]^-1`` (eq. 18), giving the closed-form model (32) in the general task space O.

>>> import symgen
>>> model = symgen.derive(symgen.load("four_bar"))
>>> model.counts.as_dict()
{'n1a': 1, 'n1u': 3, 'n3a': 0, 'n3u': 0, 'm': 1, 'nc': 3, 'np': 3, 'n': 1}
"""
from .io.loading import load
from .errors import (ConstraintError, SceneError, SingularConfigurationError, StateError,
                     SymbolicTooLargeError, SymgenError, TopologyError)
from .model import Model, ModelData, derive
from .proofs import prove
from .scene.declaration import Scene
from .math.configuration import Configuration, CosSin

__all__ = [
    "Configuration", "ConstraintError", "CosSin", "Model", "ModelData", "Scene", "SceneError",
    "SingularConfigurationError", "StateError", "SymbolicTooLargeError", "SymgenError", "TopologyError",
    "derive", "load", "prove",
]
__version__ = "0.1.0"
