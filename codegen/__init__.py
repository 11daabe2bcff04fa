"""codegen: closed-form equations of compound spatial pendulums → C, Python and LaTeX.

The data flow, one module a stage: spec → kinematics → dynamics → integrals → simplify/emit →
build → cli.  The paper's notation (digest in shared/seed/DIGEST.md) names the quantities:
k is the body index (0 the base), phi/phidot are φᵏ/φ̇ᵏ, alpha are the direction cosines.
"""
__version__ = "0.1.0"
