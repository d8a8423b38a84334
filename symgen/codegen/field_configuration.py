"""The generated code's position vector ``q`` as a configuration in any field: what the dense
references (:mod:`symgen.codegen.reference`, :mod:`symgen.codegen.reference_derivatives`) evaluate
the model at."""
from __future__ import annotations

import numpy as np

from ..errors import CodegenError
from ..math.configuration import Configuration, CosSin
from ..math.fields import Field
from ..scene.joint_kinds import joint_kind
from ..math.spatial import quaternion_matrix
from .trace import position_layout


def field_configuration(model, q, fld: Field) -> Configuration:
    """The configuration of the generated code's position vector ``q`` in ``fld``: a revolute
    angle gives ``cos`` and ``sin`` in the field, a prismatic displacement its value, and a
    quaternion ``(w, x, y, z)`` the rotation ``R(q) / |q|^2`` -- the rotation it stands for (the
    generated code assumes ``|q| = 1`` and drops the division, which differs by the float
    rounding of ``|q|``, about 1e-16). Floats are taken at their exact binary values."""
    q = np.asarray(q, dtype=float)
    layout = position_layout(model)
    size = sum(s for *_, s in layout)
    if q.shape != (size,):
        raise CodegenError(f"q must have shape ({size},) for scene {model.scene.name!r}, got {q.shape}")
    pos = {}
    for name, kind, off, _ in layout:
        kind = joint_kind(kind)
        if kind.position_is_angle:
            pos[name] = float(q[off]) if fld.dtype is float else CosSin(*fld.cos_sin(q[off]), fld.const(q[off]))
        elif kind.translates:
            pos[name] = fld.const(q[off])
        else:
            w, x, y, z = (fld.const(v) for v in q[off:off + 4])
            norm2 = w * w + x * x + y * y + z * z
            if norm2 == 0:
                raise CodegenError(f"joint {name!r}: the quaternion in q is zero")
            pos[name] = np.array([[v / norm2 for v in row] for row in quaternion_matrix(w, x, y, z)],
                                 dtype=fld.dtype)
    return Configuration(pos)
