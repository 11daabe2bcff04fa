"""codegen: closed-form equations of compound spatial pendulums → C, Python and LaTeX.

The data flow, one module a stage: spec → kinematics → dynamics → integrals → simplify/emit →
build → cli.  The paper's notation (digest in shared/seed/DIGEST.md) names the quantities:
k is the body index (0 the base), phi/phidot are φᵏ/φ̇ᵏ, alpha are the direction cosines.
"""
__version__ = "0.2.0"  # the one place of the version (pyproject.toml reads it; --version prints it)
DISTRIBUTION = "gyrochain"  # the name on the package index and of the console command
