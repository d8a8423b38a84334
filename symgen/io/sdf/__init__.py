"""SDF import: one ``<model>`` with its loops (:mod:`~symgen.io.sdf.parse`, :mod:`~symgen.io.sdf.build`)
and the Cassie biped of ``example-robot-data`` (:mod:`~symgen.io.sdf.cassie`)."""
from .build import add_sdf, scene_from_sdf, sdf_source, spanning_tree
from .parse import SdfError, SdfModel, read_sdf

__all__ = ["SdfError", "SdfModel", "add_sdf", "read_sdf", "scene_from_sdf", "sdf_source", "spanning_tree"]
