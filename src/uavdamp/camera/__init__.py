"""What the camera sees: its optics and the image of its motion (`optics`), and the image quality of a run
(`image_quality`: blur per frame, motion and jitter MTF, line-of-sight statistics)."""

from uavdamp.camera.optics import CameraModel, CameraOptics, image_displacement_px

__all__ = ["CameraModel", "CameraOptics", "image_displacement_px"]
