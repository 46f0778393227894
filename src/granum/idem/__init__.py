"""Impulse-based DEM (iDEM): rigid bodies of particles whose contacts are resolved by impulses.

Implements the impulse-based distinct element method of the seed article "力積型個別要素法
(Impulse-based Distinct Element Method)" (summary and ambiguities [A1]-[A14]:
``shared/reference/idem.md``): rigid bodies of any shape built from particles, contacts resolved
at the velocity level by an energy-conserving iteration (compression, then release of
e^2 W_comp per pair, Stronge's hypothesis), static and sliding Coulomb friction through the
K_AB matrix, velocities updated before positions, quaternion orientation, surface normals from
the smallest eigenvector of the neighbours' covariance. The only material parameters are the
restitution coefficient e and the friction coefficient mu.

Modules: :mod:`~granum.idem.bodies` (rigid bodies and builders), :mod:`~granum.idem.pca` (normals),
:mod:`~granum.idem.broadphase` (contact search), :mod:`~granum.idem.impulse` (the iteration),
:mod:`~granum.idem.rigid` (K matrix, integration), :mod:`~granum.idem.stepper` (compiled step),
:mod:`~granum.idem.solver` (:class:`IDEMSolver`), :mod:`~granum.idem.analytic` (reference
solutions of the article's verification cases).

Where the article is ambiguous, the choice made is documented in the module that implements it:
[A1] angular velocity and free rotation keeping the angular momentum (rigid); [A9] gravity
first (stepper); [A13] g = 9.81 along -z (solver); [A2]-[A4] PCA (pca); [A5] pairs and normals
(broadphase), floors and slopes as fixed sheets of particles with given normals
(bodies.plane_body); [A6]-[A8], [A11], [A12] the iteration and its "sequential"/"simultaneous"
impact modes (impulse); [A10] no position correction: penetrations are not pushed back, only
approach velocities are removed; [A14] discretisation of the test bodies (cases).
"""

from granum.idem.bodies import RigidBody, body_from_particles, box_body, plane_body
from granum.idem.solver import IDEMSolver

__all__ = ["IDEMSolver", "RigidBody", "body_from_particles", "box_body", "plane_body"]
