"""``mechfmu validate X.ssp``: a system's SSP run by every installed SSP importer, for each
parameter set it can select, at the SSP's communication step and at half of it, each result
measured against the system's solution.

The solution is the SSP's own: a plain Jacobi co-simulation of its FMUs (:mod:`.jacobi`, the
feedthrough resolved at each communication point, the inputs held over the step) at an eighth
and a sixteenth of the step, extrapolated (Richardson) to a step of zero. A co-simulation's
error against it is its coupling error, reported beside the plain Jacobi scheme's. The
importers' masters differ (FMPy and libcosim pass an output as read after the step, so an
output that follows its inputs at once reaches the inputs it feeds a step late; FMPy starts
every input at 0): an importer passes when its error at the step is at most :data:`FACTOR`
times that of its own scheme, run by mechfmu, and shrinks at half the step. FMPy labels its
rows one step early: its row at ``t`` is compared with the solution at ``t + h``.
"""

from .validate import FACTOR, validate_system

__all__ = ["FACTOR", "validate_system"]
