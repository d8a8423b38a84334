"""The MJCF four-bar and a Pinocchio CONTACT_3D twin of its closure, for the tests that compare
symgen's loop forces with Pinocchio's ``constraintDynamics`` multipliers."""
from __future__ import annotations

import pathlib

DATA = pathlib.Path(__file__).parent / "data" / "mjcf"


def four_bar_contact(pin, reference_frame):
    """``(model, robot, (data, models, datas))``: symgen's MJCF four-bar, its Pinocchio tree, and
    one ``CONTACT_3D`` between the closure's frames A and B, expressed in ``reference_frame``, with
    ``initConstraintDynamics`` done."""
    from symgen import derive, load
    from symgen.oracle.pinocchio_tree import frame_placement, tree_robot

    model = derive(load(str(DATA / "four_bar.xml")))
    con = model.scene.constraints["closure"]
    robot = tree_robot(model)
    (j1, x1), (j2, x2) = frame_placement(robot, con.frame_a), frame_placement(robot, con.frame_b)
    contact = pin.RigidConstraintModel(pin.ContactType.CONTACT_3D, robot.model, j1, x1, j2, x2, reference_frame)
    models, datas = pin.StdVec_RigidConstraintModel(), pin.StdVec_RigidConstraintData()
    models.append(contact)
    datas.append(contact.createData())
    data = robot.model.createData()
    pin.initConstraintDynamics(robot.model, data, models, datas)
    return model, robot, (data, models, datas)
