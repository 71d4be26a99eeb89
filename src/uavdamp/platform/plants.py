"""Which plant runs a strategy: `platform.backend` for the isolated mount, Exudyn where the linear plant's check fails.

The exact linear plant (`uavdamp.platform.linear_plant`) agrees with Exudyn within 0.03 % in the criterion on sine
inputs (tests/test_linear_plant.py) and within 0.12 % on the study's passive and ANFIS runs (quick config, measured).
Two cases stay on Exudyn, the reference plant (measured, default platform, 7.07/8 Hz sines, 3 s):
- the rigid mount: at its 6.7 Hz resonance pitch reaches 0.2 rad and the linear plant is 1.2-1.7 % off;
- laws that switch every solver step (on-off skyhook): there the criterion depends on the step itself (Exudyn
  0.78, 0.57, 0.44, 0.32 mm at 2, 1, 0.5, 0.25 ms, K = 10 N/m: no convergence), and the two plants' different
  discretisations of the same law differ by 2-15 %.
"""

from __future__ import annotations

from uavdamp.platform.exudyn_plant import ExudynPlant
from uavdamp.platform.linear_plant import LinearPlant
from uavdamp.platform.params import PlatformParams


class Plants:
    """The plants of one platform, built on first use: `for_run(mount, law)` picks one (module docstring)."""

    def __init__(self, params: PlatformParams):
        self.params = params
        self._built: dict[tuple[str, str], object] = {}

    def kind(self, mount: str, law) -> str:
        """ "linear" or "exudyn" for a run of `law` on `mount`."""
        every_step = law is not None and getattr(law, "update_period", None) == self.params.time_step
        if mount == "rigid" or every_step or self.params.backend == "exudyn":
            return "exudyn"
        return "linear"

    def for_run(self, mount: str, law):
        """The plant for a run of `law` (None for the rigid mount) on `mount`."""
        key = (self.kind(mount, law), mount)
        if key not in self._built:
            make = LinearPlant.from_params if key[0] == "linear" else ExudynPlant
            self._built[key] = make(self.params, mount=mount)
        return self._built[key]
