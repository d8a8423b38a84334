"""``general_chain:n=N`` is what its name says: no twist at a special angle, no zero product of
inertia or centre-of-mass coordinate (nothing for the generator to fold), the same exact numbers
on every build, and the first N links of every longer chain. Its dynamics against Pinocchio and the
rest are in the suites that run every built-in (``tests/test_oracle_tree.py`` and others)."""
from symgen.io.builtin import get_scene


def test_every_twist_inertia_and_centre_of_mass_is_general():
    scene = get_scene("general_chain:n=64")
    for joint in scene.joints.values():
        r = joint.origin.rotation
        assert r[0, 0] == 1 and r[1, 1] == r[2, 2] and r[1, 1] not in (0, 1, -1), joint.name
        assert all(x != 0 for x in joint.origin.translation), joint.name
    for body in scene.bodies.values():
        i = body.inertia
        assert all(x != 0 for x in (i[0, 1], i[0, 2], i[1, 2])), body.name
        assert all(x != 0 for x in body.com), body.name


def test_a_shorter_chain_is_the_first_links_of_a_longer_one_and_the_numbers_are_fixed():
    short, long = get_scene("general_chain:n=3"), get_scene("general_chain:n=7")
    assert [long.bodies[name] for name in short.bodies] == list(short.bodies.values())
    assert [long.joints[name] for name in short.joints] == list(short.joints.values())
    again = get_scene("general_chain:n=7")
    assert again.bodies == long.bodies and again.joints == long.joints
    assert str(long.joints["j1"].origin.translation[0]) == "143/500"      # the seed's stream, pinned
