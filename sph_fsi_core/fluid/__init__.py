"""The incompressible fluid by iterative density correction after Okaji (okaji: the per-pair passes, eqs. (6)-(9)),
its neighbour lists (neighbours: fluid-fluid half list and the wall lists) and the step that drives them (stepper)."""
