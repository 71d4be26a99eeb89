"""Signal analysis of the mount motion: spectra (`spectrum`), the dominant-frequency tracker (`tracking`) and the
inertial kinematics of an IMU's specific force and rate (`inertial`)."""
