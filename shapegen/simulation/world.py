"""The pybullet world of a block model: one rigid body per block, a static ground.

Bullet is run without a window (``DIRECT``). Each block becomes a convex-hull collision shape
whose body frame sits at the block's centroid along its principal axes, with the exact mass and
principal moments from :mod:`shapegen.simulation.inertia` (Bullet's own estimate for a hull is a
bounding box). Fixed blocks and the ground are static bodies (mass 0).

Bullet combines the friction of two touching bodies by multiplying their coefficients and
restitution likewise; every body therefore gets ``sqrt(mu)`` so that each block-block and
block-ground contact has friction ``mu``, and restitution 0.

Contacts: Bullet's default convex-hull contact (GJK, one new point per step) lets a resting stack
rock and creep by millimetres; with the hull's polyhedral features (built when the hull is loaded
from a file with ``URDF_INITIALIZE_SAT_FEATURES``) it clips touching faces against each other and
gets up to four points per pair at once, as a face contact needs. The collision margin is 0: a
margin inflates every hull, so a stack of ``n`` blocks would start ``2 n`` margins apart.

Creep: with Bullet's defaults the friction solver lets loaded joints slip a little every step (an
arch's springings spread, its crown sinks by millimetres per second). Friction anchors (each
contact remembers where it started and pulls back to it while it sticks) and full warm starting
(each step starts from the previous step's contact impulses) stop that; the time step and solver
iterations are chosen by measurement (docs/simulation.md).
"""

from __future__ import annotations

__all__ = ["World", "load_pybullet"]

import contextlib
import math
import os
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from shapegen.errors import ShapegenError
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.simulation.inertia import PrincipalInertia, principal_inertia
from shapegen.tolerances import DIVISION_FLOOR

# Half size of the ground slab, metres: large enough for any model (the slab's top is the
# ground plane; a slab rather than an infinite plane gives face contacts like between blocks).
_GROUND_HALF_SIZE = 1000.0
_GROUND_HALF_THICKNESS = 1.0


def load_pybullet():
    """The ``pybullet`` module, or a :class:`ShapegenError` telling how to install it."""
    try:
        with _stderr_silenced():
            import pybullet
    except ImportError:
        raise ShapegenError(
            "the simulation needs pybullet, which is not installed: pip install 'shapegen[sim]'"
        ) from None
    return pybullet


@contextlib.contextmanager
def _stderr_silenced():
    """Silence the C-level standard error (pybullet prints its build time there on import)."""
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (AttributeError, OSError, ValueError):  # no real file descriptor: nothing to hide
        yield
        return
    try:
        with open(os.devnull, "wb") as null:
            os.dup2(null.fileno(), 2)
            try:
                yield
            finally:
                _flush_c_stdio()
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def _flush_c_stdio() -> None:
    # The C library may buffer the message; flush it while the
    # descriptor still points to /dev/null.
    try:
        import ctypes

        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError, TypeError):
        pass


@dataclass(frozen=True)
class BodyFrame:
    """Where a block's Bullet body frame sits: its principal frame at t = 0."""

    body: int
    inertia: PrincipalInertia
    fixed: bool


class World:
    """A pybullet physics client holding ``model``'s blocks.

    Parameters
    ----------
    model
        The blocks; ``model.gravity`` (m/s^2) and ``model.ground`` (m, or None) are used.
    friction
        Coulomb coefficient of every contact (dimensionless).
    time_step
        Seconds per Bullet step.
    solver_iterations
        Iterations of Bullet's sequential-impulse contact solver per step.
    """

    def __init__(self, model: Model, friction: float, time_step: float, solver_iterations: int):
        self.pb = load_pybullet()
        self.client = self.pb.connect(self.pb.DIRECT)
        self.time_step = float(time_step)
        self.gravity = np.asarray(model.gravity, float).copy()
        pb, cid = self.pb, self.client
        pb.setGravity(*self.gravity, physicsClientId=cid)
        pb.setPhysicsEngineParameter(
            fixedTimeStep=self.time_step,
            numSolverIterations=int(solver_iterations),
            numSubSteps=0,
            enableSAT=1,
            warmStartingFactor=1.0,
            physicsClientId=cid,
        )
        self._folder = tempfile.TemporaryDirectory(prefix="shapegen-sim-")
        self._files: list[Path] = []
        surface = math.sqrt(max(float(friction), 0.0))
        self.ground = None
        if model.ground is not None:
            h, t = _GROUND_HALF_SIZE, 2.0 * _GROUND_HALF_THICKNESS
            slab = Block.box([-h, -t, -h], [h, 0.0, h])
            shape = self._hull_shape(slab, slab.vertices)
            self.ground = pb.createMultiBody(
                0.0,
                shape,
                basePosition=[0.0, float(model.ground), 0.0],
                useMaximalCoordinates=True,
                physicsClientId=cid,
            )
            self._set_surface(self.ground, surface)
        self.frames = [self._add_block(block, surface) for block in model.blocks]
        self._axes = np.array([frame.inertia.axes for frame in self.frames]).reshape(-1, 3, 3)
        self._centroids = np.array([frame.inertia.centroid for frame in self.frames]).reshape(-1, 3)

    # ------------------------------------------------------------------ set-up
    def _add_block(self, block, surface: float) -> BodyFrame:
        pb, cid = self.pb, self.client
        inertia = principal_inertia(block)
        local = (block.vertices - inertia.centroid) @ inertia.axes
        shape = self._hull_shape(block, local)
        mass = 0.0 if block.fixed else inertia.mass
        body = pb.createMultiBody(
            mass,
            shape,
            basePosition=inertia.centroid.tolist(),
            baseOrientation=_quaternion(inertia.axes),
            useMaximalCoordinates=True,
            physicsClientId=cid,
        )
        self._set_surface(body, surface)
        if not block.fixed:
            # Mass and moments in one call: Bullet zeroes the mass if the moments come alone.
            pb.changeDynamics(
                body,
                -1,
                mass=mass,
                localInertiaDiagonal=inertia.moments.tolist(),
                physicsClientId=cid,
            )
        return BodyFrame(body=body, inertia=inertia, fixed=block.fixed)

    def _hull_shape(self, block, local: np.ndarray) -> int:
        return self.pb.createCollisionShape(
            self.pb.GEOM_MESH,
            fileName=str(self._mesh_file(block, local)),
            flags=self.pb.URDF_INITIALIZE_SAT_FEATURES,
            physicsClientId=self.client,
        )

    def _mesh_file(self, block, local: np.ndarray) -> Path:
        # Bullet builds the polyhedral features that give face contacts (up to four points per
        # touching pair, by clipping) only for shapes loaded from a file, not from a vertex list.
        path = Path(self._folder.name) / f"block{len(self._files)}.obj"
        lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in local.tolist()]
        for face in block.faces:
            lines += [
                f"f {face[0] + 1} {face[i] + 1} {face[i + 1] + 1}" for i in range(1, len(face) - 1)
            ]
        path.write_text("\n".join(lines) + "\n", encoding="ascii")
        self._files.append(path)
        return path

    def _set_surface(self, body: int, surface: float) -> None:
        self.pb.changeDynamics(
            body,
            -1,
            lateralFriction=surface,
            restitution=0.0,
            rollingFriction=0.0,
            spinningFriction=0.0,
            linearDamping=0.0,
            angularDamping=0.0,
            activationState=self.pb.ACTIVATION_STATE_DISABLE_SLEEPING,
            collisionMargin=0.0,
            frictionAnchor=1,
            physicsClientId=self.client,
        )

    # ------------------------------------------------------------------ running
    def set_gravity(self, gravity: np.ndarray) -> None:
        """Change the acceleration of gravity, m/s^2 (the shake adds a pseudo-acceleration)."""
        self.pb.setGravity(*np.asarray(gravity, float), physicsClientId=self.client)

    def apply_force(self, index: int, force: np.ndarray, point: np.ndarray) -> None:
        """Apply ``force`` (N, world) at ``point`` (m, world) on block ``index`` for one step."""
        self.pb.applyExternalForce(
            self.frames[index].body,
            -1,
            np.asarray(force, float).tolist(),
            np.asarray(point, float).tolist(),
            self.pb.WORLD_FRAME,
            physicsClientId=self.client,
        )

    def step(self) -> None:
        """Advance by one time step."""
        self.pb.stepSimulation(physicsClientId=self.client)

    def poses(self) -> tuple[np.ndarray, np.ndarray]:
        """Every block's motion since t = 0 as a rigid map ``x -> R x + t``.

        Returns
        -------
        rotations
            ``(n, 3, 3)``.
        translations
            ``(n, 3)``, metres.
        """
        from scipy.spatial.transform import Rotation

        pb, cid = self.pb, self.client
        placed = [
            pb.getBasePositionAndOrientation(frame.body, physicsClientId=cid)
            for frame in self.frames
        ]
        positions = np.array([position for position, _ in placed], float).reshape(-1, 3)
        quaternions = np.array([orientation for _, orientation in placed], float).reshape(-1, 4)
        # x_now = B_now (axes^T (x0 - c0)) + p_now, with B_now the body's orientation.
        rotations = Rotation.from_quat(quaternions).as_matrix().reshape(-1, 3, 3) @ np.transpose(
            self._axes, (0, 2, 1)
        )
        translations = positions - np.einsum("nij,nj->ni", rotations, self._centroids)
        return rotations, translations

    def velocities(self) -> tuple[np.ndarray, np.ndarray]:
        """Every block's centre-of-mass velocity (m/s) and spin (rad/s), ``(n, 3)`` each."""
        pb, cid = self.pb, self.client
        moving = [pb.getBaseVelocity(frame.body, physicsClientId=cid) for frame in self.frames]
        linear = np.array([v for v, _ in moving], float).reshape(-1, 3)
        angular = np.array([w for _, w in moving], float).reshape(-1, 3)
        return linear, angular

    def close(self) -> None:
        """Disconnect the physics client."""
        if self.client is not None:
            self.pb.disconnect(physicsClientId=self.client)
            self.client = None
        self._folder.cleanup()

    def __enter__(self) -> World:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _quaternion(rotation: np.ndarray) -> list[float]:
    """The unit quaternion ``[x, y, z, w]`` of a proper rotation matrix."""
    m = np.asarray(rotation, float)
    trace = np.trace(m)
    if trace > 0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = [(m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, s / 4]
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(max(1.0 + m[i, i] - m[j, j] - m[k, k], DIVISION_FLOOR))
        q = [0.0, 0.0, 0.0, 0.0]
        q[i] = s / 4
        q[j] = (m[j, i] + m[i, j]) / s
        q[k] = (m[k, i] + m[i, k]) / s
        q[3] = (m[k, j] - m[j, k]) / s
    norm = math.sqrt(sum(v * v for v in q))
    return [v / norm for v in q]
