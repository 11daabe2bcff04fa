"""codegen: closed-form equations of compound spatial pendulums → C, Python and LaTeX.

The data flow, one module a stage: spec → the derivation stages (kinematics → dynamics →
integrals, aba, derivatives, world, quadratures) → assemble (the Model, forms chosen by op count)
→ printers (c, python, latex; the kernels) and build → pipeline (derive, render, compile: the one
route) → the commands (generate, simulate, steady, sweep, animate, plot) → cli.  No module imports
a layer above its own ([tool.importlinter] in pyproject.toml).

The notation is the paper's ("The compound spatial pendulum", with Kharlamov's equations of
motion of a system of rigid bodies): k is the body index (0 the base), phi/phidot are φᵏ/φ̇ᵏ,
alpha are the direction cosines; equation numbers in comments are the paper's.
"""
__version__ = "0.2.0"  # the one place of the version (pyproject.toml reads it; --version prints it)
DISTRIBUTION = "gyrochain"  # the name on the package index and of the console command
