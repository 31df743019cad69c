"""Numerics shared by every phase: the kernel (kernels), neighbour search (neighbours), the SIMD pair blocks of the
pair passes (pair_blocks) and symmetric-tensor helpers (tensors). No physics of a phase lives here."""
