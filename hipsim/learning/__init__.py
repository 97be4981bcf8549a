"""Learning the cycle from run to run (iterative learning control) and commands a drive takes.

- :mod:`~hipsim.learning.filters`: the periodic zero-phase filter Q, a drive's lag, derivatives of one period;
- :mod:`~hipsim.learning.law`: the update u_{k+1} = Q(u_k + L·e_k) and its convergence figures;
- :mod:`~hipsim.learning.step`: one step from a log, the model's first command, the loop over cycles on a runner;
- :mod:`~hipsim.learning.records`: the typed summary of a step;
- :mod:`~hipsim.learning.servo`: a cycle runner on a simulated servo loop (``simulate --learn``);
- :mod:`~hipsim.learning.export`: per-motor position–velocity–time tables with the torque feed-forward.
"""

from .law import LearningLaw
from .records import LearnSummary
from .step import CycleLog, LearnStep, first_command, learn_cycles, learning_step

__all__ = ["CycleLog", "LearnStep", "LearnSummary", "LearningLaw", "first_command", "learn_cycles", "learning_step"]
