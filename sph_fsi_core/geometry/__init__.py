"""A scene from geometry (scenes/geometry.py): shapes placed in the world (shapes), the lattice sites they hold
(lattice), and the part and probe lists of a scene file (parts)."""
