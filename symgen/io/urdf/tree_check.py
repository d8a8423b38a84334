"""The joints of a parsed URDF form one tree: parents and children exist, one parent per link, one
root, no cycle (:func:`check_tree`, run by :func:`symgen.io.urdf.parse.read_urdf`)."""
from __future__ import annotations


def check_tree(robot) -> None:
    """The :class:`~symgen.io.urdf.parse.UrdfRobot` ``robot``: parents and children exist, one parent per link, one root, no cycle."""
    parent_joint: dict[str, str] = {}
    for j in robot.joints.values():
        for role in ("parent", "child"):
            link = getattr(j, role)
            if link not in robot.links:
                raise robot.error(f"joint {j.name!r}", f"{role} link {link!r} does not exist", j.line)
        if j.child in parent_joint:
            first = robot.joints[parent_joint[j.child]]
            raise robot.error(f"link {j.child!r}", f"is the child of two joints, {first.name!r} (line {first.line}) "
                                                   f"and {j.name!r}: a URDF must be a tree", j.line)
        parent_joint[j.child] = j.name
        robot.children.setdefault(j.parent, []).append(j.name)
    roots = [name for name in robot.links if name not in parent_joint]
    if not roots:
        raise _cycle_error(robot, parent_joint, next(iter(robot.links)))
    if len(roots) > 1:
        stray = roots[1]
        raise robot.error(f"link {stray!r}", f"is not connected to the root link {roots[0]!r} by any joint "
                                             f"(a URDF has exactly one root)", robot.links[stray].line)
    robot.root = roots[0]
    reached, stack = {robot.root}, [robot.root]
    while stack:
        for jname in robot.children.get(stack.pop(), ()):
            child = robot.joints[jname].child
            reached.add(child)
            stack.append(child)
    missing = [name for name in robot.links if name not in reached]
    if missing:
        raise _cycle_error(robot, parent_joint, missing[0])


def _cycle_error(robot, parent_joint: dict, start: str):
    """Follow parent joints from ``start`` until a link repeats; name the joints of the cycle."""
    seen, link = [], start
    while link not in seen:
        seen.append(link)
        link = robot.joints[parent_joint[link]].parent
    cycle = [parent_joint[x] for x in seen[seen.index(link):]]
    first = robot.joints[cycle[0]]
    return robot.error(f"joint {first.name!r}", f"joints {', '.join(map(repr, cycle))} form a cycle "
                                                "(a URDF must be a tree)", first.line)
