# Your implementation of the component LevelSensor: this file is yours.
# colcon-robmosys created it once and never writes it again; the skeleton
# src-skel/level_sensor/LevelSensor_impl_skel.py of the generated package
# shows what the model asks for after the model changes.
"""Implementation of the functions of LevelSensor that the model leaves open."""

from level_sensor.LevelSensor import LevelSensor


class LevelSensor_impl(LevelSensor):
    """The component LevelSensor with its user-written functions."""

    def fAbove(self, activation, event) -> bool:
        """
        Run the function fAbove of the model.

        The condition of an activation.
        """
        return event.level >= activation.threshold
