"""What shakes the mount: the vibration sources and the named uses of them (the study's cases).

`excitation`: a helicopter run's, a measured flight's or a stated source's motion at the mount, windowed,
high-passed and scaled into the study's cases, brought onto one grid (`on_common_grid`); mono-frequency sines (the
paper's inputs). `stated`, `profiles` and `levels`: sources defined by their parameters and their levels in the
field's units. `flight_log`: PX4 and ArduPilot logs. The resampler of one motion onto a solver grid lives beside
the motion's type (`uavdamp.contract.on_grid`).
"""
