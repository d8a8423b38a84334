"""MJCF sites placed by ``fromto``: the frame MuJoCo compiles (``site_pos``, ``site_quat``), and
MuJoCo's refusals. MuJoCo's z axis points from ``to`` back to ``from`` (the other direction would
differ from ``site_quat`` by a half turn, which the comparison sees)."""
import mujoco
import numpy as np
import pytest

from symgen.io.mjcf import parse_mjcf, scene_from_mjcf
from symgen.io.mjcf.values import MjcfError
from symgen.math.configuration import quaternion_rotation

SITES = """<mujoco><compiler angle="degree"/><worldbody>
<body name="b" pos="0.1 0.2 0.3" euler="10 20 30"><joint name="j"/><geom size="0.1"/>
<frame pos="0 0.1 0" euler="0 0 90">
<site name="slant" type="capsule" size="0.01" fromto="0 0 0 1 1 -1"/>
</frame>
<site name="down" type="box" size="0.01" fromto="0.1 0 0.3 0.1 0 -0.2"/>
<site name="up" type="cylinder" size="0.01" fromto="0.1 0 0.3 0.1 0 0.5"/>
<site name="flat" type="ellipsoid" size="0.01" euler="0 0 45" fromto="0.2 0 0.1 0.5 0.4 0.1"/>
{extra}</body></worldbody></mujoco>"""


def _write(tmp_path, extra=""):
    path = tmp_path / "sites.xml"
    path.write_text(SITES.format(extra=extra))
    return str(path)


def test_fromto_sites_have_mujocos_compiled_frames(tmp_path):
    """Four directions (slanted inside a turned frame, straight down, straight up, level with an
    orientation that fromto overrides) against MuJoCo's body-frame ``site_pos`` and ``site_quat``."""
    path = _write(tmp_path)
    m = mujoco.MjModel.from_xml_path(path)
    sites = parse_mjcf(path).sites
    assert {s.name for s in sites} == {"slant", "down", "up", "flat"}
    for s in sites:
        i = m.site(s.name).id
        assert np.max(np.abs(np.array(s.pos, dtype=float).ravel() - m.site_pos[i])) < 1e-14, s.name
        assert np.max(np.abs(np.array(s.rot, dtype=float) - quaternion_rotation(m.site_quat[i]))) < 1e-14, s.name
    assert "slant" in scene_from_mjcf(path).frames


@pytest.mark.parametrize("extra, words", [
    ('<site name="ball" size="0.01" fromto="0 0 0 0 0 1"/>', "fromto needs a site of type"),
    ('<site name="both" type="capsule" size="0.01" pos="1 0 0" fromto="0 0 0 0 0 1"/>', "both pos and fromto"),
    ('<site name="point" type="capsule" size="0.01" fromto="0 0 1 0 0 1"/>', "must differ"),
])
def test_fromto_sites_mujoco_refuses_are_typed_errors_naming_the_site(tmp_path, extra, words):
    path = _write(tmp_path, extra)
    with pytest.raises(Exception):            # MuJoCo refuses the file too
        mujoco.MjModel.from_xml_path(path)
    with pytest.raises(MjcfError, match=words) as info:
        parse_mjcf(path)
    assert info.value.line == 9
