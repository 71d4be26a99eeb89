"""The six-axis isolator as an Exudyn model: one rigid body on N spring-dampers to ground (assembly and modes).

The payload is an ObjectRigidBody whose node (Tait-Bryan angles, `NodeType.RotationRxyz`: no constraint
equation) sits at the payload's reference point, with the centre of mass and inertia of `Payload`; each element
is an ObjectConnectorCartesianSpringDamper (stiffness and damping along the global axes, the mount axes at rest)
between a ground point and the body point at its position; an element's own rotational stiffness, if any, is an
ObjectConnectorRigidBodySpringDamper (rotational block only) at the same point. The mount is held still (ground):
this model is the independent check of `uavdamp.platform.six_axis`'s matrices and modes.
"""

from __future__ import annotations

from dataclasses import dataclass

import exudyn as exu
import numpy as np
from exudyn.itemInterface import ObjectGround
from exudyn.utilities import RigidBodyInertia

from uavdamp.platform.six_axis import SixAxisIsolator


@dataclass
class ExudynIsolator:
    """An assembled model: the system container (kept alive with the system), the system and the body."""

    system_container: exu.SystemContainer
    mbs: exu.MainSystem
    body: int
    node: int


def build(isolator: SixAxisIsolator) -> ExudynIsolator:
    """Assemble the payload on its elements (the mount held still), at rest at the reference configuration; the
    weightless isolator only (gravity 0: this check is of the elastic stiffness and the mass matrix)."""
    if isolator.gravity != 0:
        raise ValueError("platform.six_axis.gravity_m_s2: the Exudyn check builds the weightless isolator (0)")
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    p = isolator.payload
    inertia = RigidBodyInertia(
        mass=p.mass, inertiaTensor=np.asarray(p.inertia, dtype=float), com=np.asarray(p.com), inertiaTensorAtCOM=True
    )
    body = mbs.CreateRigidBody(
        referencePosition=[0.0, 0.0, 0.0], inertia=inertia, nodeType=exu.NodeType.RotationRxyz, show=False
    )
    ground = mbs.AddObject(ObjectGround())
    for e in isolator.elements:
        mbs.CreateCartesianSpringDamper(
            itemNumbers=[ground, body],
            localPosition0=list(e.position),
            localPosition1=list(e.position),
            stiffness=list(e.stiffness),
            damping=list(e.damping),
            show=False,
        )
        if max(e.rotational_stiffness) > 0 or max(e.rotational_damping) > 0:
            k, c = np.zeros((6, 6)), np.zeros((6, 6))
            k[3:, 3:], c[3:, 3:] = np.diag(e.rotational_stiffness), np.diag(e.rotational_damping)
            mbs.CreateRigidBodySpringDamper(
                itemNumbers=[ground, body],
                localPosition0=list(e.position),
                localPosition1=list(e.position),
                stiffness=k,
                damping=c,
                show=False,
            )
    mbs.Assemble()
    node = mbs.GetObject(body)["nodeNumber"]
    return ExudynIsolator(sc, mbs, body, node)


def modes(isolator: SixAxisIsolator) -> tuple[np.ndarray, np.ndarray]:
    """Undamped natural frequencies (6,) Hz ascending and mode shapes (6, 6) (columns over the node's x, y, z
    m and Tait-Bryan angles rad, Exudyn's normalisation) by Exudyn's eigen-analysis at the rest configuration."""
    model = build(isolator)
    values, vectors = model.mbs.ComputeODE2Eigenvalues()
    values = np.asarray(values, dtype=float)
    order = np.argsort(values)
    return np.sqrt(np.abs(values[order])) / (2 * np.pi), np.asarray(vectors)[:, order]
