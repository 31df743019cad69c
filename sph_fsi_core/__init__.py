"""sph_fsi_core: the 3D SPH simulator of Satake et al. (elastic solid, incompressible fluid, coupling).

Pure Python + Numba; never imports ROS. Entry points: scene.load_scene, simulation.Simulation, run.run_scene.
"""
__version__ = "0.1.0"
