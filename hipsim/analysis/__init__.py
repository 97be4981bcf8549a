"""Model runs: one call picks a model and runs it along a trajectory, in one piece or streamed, and the models' cross-check.

Pure: functions here return data; they never print and never import :mod:`hipsim.present`.
The names load on first use (PEP 562), so that :mod:`hipsim.analysis.registry`,
which the command line reads for its choices, costs no model's import.
"""

__all__ = ["analyse", "compare_models", "differences", "stream_run"]


def __getattr__(name: str):
    """A public name, imported on first use."""
    if name == "analyse":
        from .runs import analyse as value
    elif name == "compare_models":
        from .crosscheck import compare_models as value
    elif name == "differences":
        from .crosscheck import differences as value
    elif name == "stream_run":
        from .streaming import stream_run as value
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
