"""The built-in scenes as YAML files (``<name>.yaml`` or ``<name>_<param><value>.yaml``).

They are written by ``symgen export`` from :mod:`symgen.io.builtin`; a test checks that each file
loads to the same scene as its Python builder.
"""
from pathlib import Path

#: file name -> built-in spec
FILES = {
    "arm_on_plane.yaml": "arm_on_plane",
    "multi_arm_h2.yaml": "multi_arm:h=2",
    "multi_arm_h3.yaml": "multi_arm:h=3",
    "four_bar.yaml": "four_bar",
    "five_bar.yaml": "five_bar",
    "stewart.yaml": "stewart",
    "chain_n6.yaml": "chain:n=6",
    "general_chain_n7.yaml": "general_chain:n=7",
}


def path(file_name: str) -> Path:
    """Location of a built-in scene file inside the installed package."""
    return Path(__file__).with_name(file_name)
