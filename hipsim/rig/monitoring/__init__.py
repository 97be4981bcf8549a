"""Monitoring a long wear test: the snapshots, each snapshot's friction estimate, the control chart, the table.

Modules: :mod:`~hipsim.rig.monitoring.snapshots` (the files, which are complete, their identity, windows),
:mod:`~hipsim.rig.monitoring.snapshot_log` (one snapshot read once by the rig-log reader),
:mod:`~hipsim.rig.monitoring.reference` (the identified machine held fixed),
:mod:`~hipsim.rig.monitoring.monitor_fit` (a snapshot's estimate),
:mod:`~hipsim.rig.monitoring.control_chart` (the two-sided EWMA chart),
:mod:`~hipsim.rig.monitoring.findings` (alarms, notices, stations, the load cell, missing snapshots),
:mod:`~hipsim.rig.monitoring.monitor_table` (the table as a file),
:mod:`~hipsim.rig.monitoring.monitor_run` (:func:`monitor`, also ``hipsim.monitor``) and
:mod:`~hipsim.rig.monitoring.watch` (a test in progress).
"""

from .monitor_run import monitor

__all__ = ["monitor"]
