# Your implementation of the component Subscriber: this file is yours.
# colcon-robmosys created it once and never writes it again; the skeleton
# src-skel/subscriber/Subscriber_impl_skel.py of the generated package
# shows what the model asks for after the model changes.
"""Implementation of the functions of Subscriber that the model leaves open."""

from subscriber.Subscriber import Subscriber


class Subscriber_impl(Subscriber):
    """The component Subscriber with its user-written functions."""

    def fListening(self, commobj) -> None:
        """Print the size of each map received."""
        self.get_logger().info(
            f'got map data: width {commobj.ogm.width}, height {commobj.ogm.height}, '
            f'resolution {commobj.ogm.resolution:.2f}')
