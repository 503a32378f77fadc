# Your implementation of the component Receiver: this file is yours.
# colcon-robmosys created it once and never writes it again; the skeleton
# src-skel/receiver/Receiver_impl_skel.py of the generated package
# shows what the model asks for after the model changes.
"""Implementation of the functions of Receiver that the model leaves open."""

from receiver.Receiver import Receiver


class Receiver_impl(Receiver):
    """The component Receiver with its user-written functions."""

    def fReceive(self, commobj) -> None:
        """Log each text received."""
        self.get_logger().info(
            f'received {commobj.data} {commobj.seq} value {commobj.value:.1f}')
