from setuptools import setup

package_name = 'handwritten_nodes'

setup(
    name=package_name,
    version='0.1.0',
    packages=[package_name],
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='RobMoSys Example Team',
    maintainer_email='robmosys-examples@example.com',
    description='Two hand-written rclpy nodes: a plain talker and a lifecycle listener.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'talker = handwritten_nodes.talker:main',
            'lifecycle_listener = handwritten_nodes.lifecycle_listener:main',
        ],
    },
)
