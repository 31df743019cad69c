"""Fluid-structure coupling (Satake et al. sec. 2.3): solver.py holds the coupling's state and its verbs, forces.py
its pair passes."""
