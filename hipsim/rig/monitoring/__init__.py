"""Monitoring a long wear test: the snapshots, each snapshot's friction estimate, the control chart, the table.

Modules: :mod:`~hipsim.rig.monitoring.snapshots`, :mod:`~hipsim.rig.monitoring.monitor_fit`,
:mod:`~hipsim.rig.monitoring.control_chart`, :mod:`~hipsim.rig.monitoring.monitor_table`
and :mod:`~hipsim.rig.monitoring.monitor_run` (:func:`monitor`, also ``hipsim.monitor``).
"""

from .monitor_run import monitor

__all__ = ["monitor"]
