"""The elastic solid: Gray, Monaghan & Swift (2001) in 3D (gray2001: the paper's SPH gradient, stress rate, momentum
and artificial stress), the fitted velocity gradients (fitted_gradient: kernel-corrected linear and quadratic
least-squares fits), the strain-gradient nodal integration (gradient_integration), the named schemes that combine
them (schemes) and the compiled leapfrog that advances it (stepper)."""
