# Your implementation of the component AddServer: this file is yours.
# colcon-robmosys created it once and never writes it again; the skeleton
# src-skel/add_server/AddServer_impl_skel.py of the generated package
# shows what the model asks for after the model changes.
"""Implementation of the functions of AddServer that the model leaves open."""

from add_server.AddServer import AddServer
from example_msgs.srv import AddTwoInts


class AddServer_impl(AddServer):
    """The component AddServer with its user-written functions."""

    def fAdd(self, request, response) -> AddTwoInts.Response:
        """
        Run the function fAdd of the model.

        Answer a request with the sum.
        """
        response.sum = request.a + request.b
        self.get_logger().info(f'answering {request.a} + {request.b}')
        return response
