"""The machine: its parameter set (SI inside) and the model files generated from it.

Layer 1 of hipsim: imports nothing of hipsim but :mod:`hipsim.exceptions` and
:mod:`hipsim.files`.
"""

from .model_files import urdf_text, write_urdf
from .parameters import Parameters, load_parameters, slender_levers

__all__ = ["Parameters", "load_parameters", "slender_levers", "urdf_text", "write_urdf"]
