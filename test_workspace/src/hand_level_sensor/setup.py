from setuptools import setup

package_name = 'hand_level_sensor'

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
    description='A hand-written node that serves an event port with robmosys_runtime.',
    license='Apache-2.0',
    tests_require=['pytest'],
    entry_points={
        'console_scripts': [
            'hand_level_sensor = hand_level_sensor.sensor:main',
        ],
    },
)
