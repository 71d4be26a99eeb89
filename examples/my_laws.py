"""A worked plug-in law (docs/submit-a-law.md): frequency-ratio switching, outside the package.

Name this file in the config's top-level ``plugins`` and its strategy in ``study.strategies`` and/or
``benchmark.controllers``:

    plugins: [examples/my_laws.py]
    benchmark: {controllers: [rigid, passive_tuned, ..., frequency_ratio]}

The law: a mass-spring isolator transmits less than a rigid mount only above sqrt(2) f_n (f_n = sqrt(K / m) / 2 pi,
m the platform mass on the isolator), where damping only hurts; below it damping limits the resonance. So every
update period the law tracks the dominant frequency f of the mount input (both axes, the larger one: the study's
tracker, ``study.tracking``) and demands c_low above sqrt(2) f_n, c_high below, c_high until a frequency is known.
c_high is the damper's upper bound; c_low its lower bound (plant clips: `uavdamp.contract.clip`).
"""

from __future__ import annotations

import functools
import math

from uavdamp.signals import tracking
from uavdamp.study.strategies import Context, Strategy, register


class FrequencyRatio:
    """C = c_low when the tracked input frequency is above sqrt(2) f_n, else c_high (N s m-1); every update."""

    name = "frequency_ratio"
    update_period = None  # the platform's update period (platform.isolator.update_period_s)

    def __init__(self, natural_hz: float, c_low: float, c_high: float, track):
        self.natural_hz, self.c_low, self.c_high, self.track = float(natural_hz), float(c_low), float(c_high), track

    def reset(self) -> None:
        pass

    def __call__(self, observation) -> float:
        freqs = [self.track(observation.time, x, observation.t_now) for x in (observation.mount_y, observation.mount_z)]
        known = [f for f in freqs if math.isfinite(f)]
        if not known:
            return self.c_high
        return self.c_low if max(known) > math.sqrt(2.0) * self.natural_hz else self.c_high


@register("frequency_ratio")
def frequency_ratio(ctx: Context) -> Strategy:
    mass = ctx.params.structure.total_mass  # kg on the isolator
    natural_hz = math.sqrt(ctx.stiffness / mass) / (2.0 * math.pi)
    track = functools.partial(tracking.frequency_causal, options=ctx.options.tracking)
    law = FrequencyRatio(natural_hz, ctx.bounds.c_min, ctx.bounds.c_max, track)
    info = {"frequency_ratio_natural_hz": (natural_hz, "Hz", "isolator natural frequency sqrt(K / m) / 2 pi")}
    return Strategy("frequency_ratio", "isolated", law, info)
