"""The derivation, stage by stage in the paper's notation: the exact algebra and the straight-line
program it is written in, kinematics, dynamics (mass matrix and forces), the integrals, the
articulated-body recursion, the derivatives, the two-body quadratures, the regressor and base
parameters, and assemble (the Model, its forms chosen by operation count); reference is the
independent numeric model the tests compare with.

Modules: exact, algebra, program, vec3, platform, straightline, trigform, reference, kinematics,
loopform, dynamics, integrals, derivatives, quadratures, world, aba, regressor, baseparams,
assemble.  May import: chainspec (the layers of [tool.importlinter] in pyproject.toml).
"""
