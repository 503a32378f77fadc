# Your implementation of the component AddClient: this file is yours.
# colcon-robmosys created it once and never writes it again; the skeleton
# src-skel/add_client/AddClient_impl_skel.py of the generated package
# shows what the model asks for after the model changes.
"""Implementation of the functions of AddClient that the model leaves open."""

from add_client.AddClient import AddClient


class AddClient_impl(AddClient):
    """The component AddClient with its user-written functions."""

    def fOnAnswer(self, commobj) -> None:
        """Log the answer of an asynchronous call."""
        self.get_logger().info(f'callback answer: {commobj.sum}')
