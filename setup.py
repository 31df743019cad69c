from glob import glob

from setuptools import find_packages, setup

package_name = 'sph_fsi'

setup(
    name=package_name,
    version='0.1.0',
    # sph_fsi (ROS node + CLI), sph_fsi_core (simulator, no ROS), sph_fsi_core.scenes
    packages=find_packages(exclude=['test', 'test.*', 'bench', 'bench.*']),
    # Reference data read by sph_fsi_core/answers/references.py, next to the module.
    package_data={'sph_fsi_core.answers': ['reference_data/*.csv']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/config', glob('config/*.yaml')),
        # geometry scenes to start from, with their mesh files (read relative to the scene file)
        ('share/' + package_name + '/config/examples', glob('config/examples/*.yaml') + glob('config/examples/*.stl')),
    ],
    # Dependencies are declared once, in requirements.txt (pip) and package.xml (rosdep).
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='sph_fsi developers',
    maintainer_email='sph-fsi@example.org',
    description='3D SPH fluid-structure interaction simulator (Numba) with a ROS 2 node',
    license='Apache-2.0',
    python_requires='>=3.10',
    entry_points={
        'console_scripts': [
            'sph-fsi = sph_fsi.cli:main',
            'sph_fsi_node = sph_fsi.node:main',
        ],
    },
)
