"""Damping laws and the devices that apply them: the study's laws (`laws`: passive, the ANFIS schedule, the
reference table), the benchmark's semi-active laws (`semi_active`: skyhook, groundhook, ...), the clairvoyant bound
(`clairvoyant`), damper models (`dampers`: ideal, first-order lag, MR) and their actuation (`actuation`)."""
