"""Dynamic contact forces linear in their parameters, and their regressor ``Y_m`` (eq. 37).

``eta_m`` acts along the contact frame's twist components selected by the scene
(``contact_forces: {frame, components}``, Step 9); ``v_c = D_m qd`` are those components of the
frame's velocity. The law here is friction-like, per component ``i``::

    eta_m,i = b_i v_c,i + c_i sign(v_c,i)                    (viscous and Coulomb)

so that ``D_m^T eta_m = Y_m P_m`` with ``P_m = [b_1 .. b_k, c_1 .. c_k]`` and
``Y_m = D_m^T [diag(v_c), diag(sign v_c)]`` (``n x 2k``). The parameters are named after the frame
(``b_vx_object``, ``c_wz_object``). ``eta_m`` enters like the joints' friction: it is part of
``G`` in model (32), opposing the motion when ``b, c > 0``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import ControlInputError
from .parameters import Parameter


@dataclass(frozen=True)
class ContactLaw:
    """Viscous ``b`` and Coulomb ``c`` coefficients per contact component (scene order)."""

    frame: str
    components: tuple[str, ...]
    viscous: tuple
    coulomb: tuple

    def __post_init__(self):
        for what, values in (("viscous", self.viscous), ("coulomb", self.coulomb)):
            if len(values) != len(self.components):
                raise ControlInputError(f"contact law of frame {self.frame!r}: {len(values)} {what} "
                                        f"coefficients for {len(self.components)} components")

    @classmethod
    def for_scene(cls, scene, viscous=0.0, coulomb=0.0) -> "ContactLaw":
        """The law on the scene's contact components, with scalar or per-component coefficients."""
        cf = scene.contact_forces
        if cf is None:
            raise ControlInputError(f"scene {scene.name!r} declares no contact forces (eta_m)")
        k = len(cf.components)
        as_tuple = (lambda v: tuple(np.broadcast_to(np.asarray(v, dtype=object), (k,))))
        return cls(cf.frame, tuple(cf.components), as_tuple(viscous), as_tuple(coulomb))

    def parameters(self) -> list[Parameter]:
        """``P_m`` of eq. (37) as known parameters (make them uncertain with
        :meth:`~symgen.control.parameters.ParameterSet.with_uncertainty`)."""
        return ([Parameter(self.frame, f"b_{c}", v) for c, v in zip(self.components, self.viscous)]
                + [Parameter(self.frame, f"c_{c}", v) for c, v in zip(self.components, self.coulomb)])

    def forces(self, v_c, field) -> np.ndarray:
        """``eta_m`` at the contact velocity components ``v_c``."""
        return contact_basis(v_c, field) @ np.array(list(self.viscous) + list(self.coulomb), dtype=field.dtype)


def contact_velocity(data) -> np.ndarray:
    """``v_c = D_m qd`` (Step 9's map at the actual rates)."""
    return data.maps.D_m.v @ data.qd


def contact_basis(v_c, field) -> np.ndarray:
    """``[diag(v_c), diag(sign v_c)]`` (``k x 2k``): ``eta_m = basis @ P_m``."""
    k = len(v_c)
    out = field.zeros((k, 2 * k))
    for i, v in enumerate(v_c):
        out[i, i] = v
        out[i, k + i] = field.sign(v)
    return out


def contact_regressor(data) -> np.ndarray:
    """``Y_m = D_m^T [diag(v_c), diag(sign v_c)]`` of eq. (37), ``n x 2k``."""
    return data.maps.D_m.v.T @ contact_basis(contact_velocity(data), data.field)
