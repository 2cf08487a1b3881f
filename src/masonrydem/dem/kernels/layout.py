"""Layouts shared by the kernels and the Python side: law ids, the columns
of the parameter, state and history arrays, and the named containers of
arrays that the kernels take.

The containers are NamedTuples of numpy arrays (numba passes and caches
them like tuples).  Each groups what one concept needs, structure of
arrays: a row per node, tetrahedron or sub-contact.  A container that a
model does not need holds empty arrays (``empty_*``), so that every kernel
has one signature.

**Lanes.**  The kernels advance S simulations of one mesh in lock-step,
one per lane (a batch: dem/batch.py; a single run is a batch of one).
What the lanes share, the mesh and its topology, has no lane axis; what
each lane has of its own (displacements, masses, materials, stresses,
law states) carries the lane axis last, innermost, so that a gather by
node index reads one contiguous vector of S values and the arithmetic
runs across the lanes in the vector registers.  The sub-contacts' own
arrays are (sub-contacts x S, columns) in Fortran order: row s S + b is
sub-contact s of lane b, and a column is contiguous over all of them.
Every lane's values are computed by the same operations in the same
order as a run alone: a lane gives the same bits in any batch.

Conventions: SI units, tension positive; zone stresses as
(xx, yy, zz, xy, yz, zx).
"""
from typing import NamedTuple

import numpy as np

# --- law ids (the tables of laws.py name them) --------------------------------
ZONE_NONE = -1          # rigid blocks: no zones
ZONE_ELASTIC = 0
ZONE_MOHR_COULOMB = 1

JOINT_ELASTIC = 0
JOINT_BRITTLE_COULOMB = 1
JOINT_COUPLED = 2
JOINT_BEARING = 3
JOINT_FRICTION = 4
JOINT_COUPLED_EXPONENTIAL = 5
JOINT_COUPLED_ADDITIVE = 6
JOINT_COUPLED_FRICTION_SLIP = 7
JOINT_COUPLED_TOTAL_SLIP = 8

# --- zone parameter / state columns (per tetrahedron) ------------------------
ZP_K, ZP_G, ZP_FT, ZP_C, ZP_NPHI, ZP_GF = 0, 1, 2, 3, 4, 5
N_ZP = 6
ZS_EPT, ZS_EULT, ZS_H = 0, 1, 2  # plastic tensile strain, its ultimate value, crack band width
N_ZS = 3

# --- joint parameter / state columns (per sub-contact) ----------------------
JP_KN, JP_KS, JP_FT, JP_C, JP_TANPHI, JP_WU, JP_SU, JP_TANPHI_R, JP_TANPSI = 0, 1, 2, 3, 4, 5, 6, 7, 8
N_JP = 9
JS_SN, JS_T1, JS_T2, JS_WP, JS_SP, JS_D = 0, 1, 2, 3, 4, 5
N_JS = 6

# --- history: one row per step ----------------------------------------------
# step number, unbalanced-force ratio, kinetic energy, then per monitor
# group g its force (column H_MON + 2 g) and displacement (H_MON + 2 g + 1)
H_STEP, H_RATIO, H_KE, H_MON = 0, 1, 2, 3


def h_force(g):
    """History column of monitor group g's force (its reaction)."""
    return H_MON + 2 * g


def h_disp(g):
    """History column of monitor group g's mean displacement."""
    return H_MON + 2 * g + 1


def h_width(ngroups):
    return H_MON + 2 * ngroups


# status codes returned by the step kernel
ST_OK = 0
ST_NONFINITE = 1


class Nodes(NamedTuple):
    """Per node of the deformable blocks, or per rigid body (its reference
    point, the centroid); the strips (rigid bearing plates) follow as one
    node each."""
    x0: np.ndarray      # (n, 3) initial position
    u: np.ndarray       # (n, 3, S) displacement
    v: np.ndarray       # (n, 3, S) velocity
    f: np.ndarray       # (n, 3, S) force of the last step (on prescribed components: the reaction)
    mass: np.ndarray    # (n, 3, S) inertial mass per component (scaled in quasi-static mode)
    mgrav: np.ndarray   # (n, S) physical mass, which gravity loads
    fixed: np.ndarray   # (n, 3) uint8: the component's velocity is prescribed
    vpres: np.ndarray   # (n, 3, S) prescribed velocity (times the velocity factor)
    fext: np.ndarray    # (n, 3, S) applied force, times the load factor (deformable blocks)


class Zones(NamedTuple):
    """Constant-strain tetrahedra and their mixed-discretization groups."""
    tets: np.ndarray    # (nt, 4) node indices
    dn: np.ndarray      # (nt, 9) grad N_1, grad N_2, grad N_3 (grad N_0 = -sum)
    vol: np.ndarray     # (nt,) volume
    wt: np.ndarray      # (nt,) weight (1/2 for the two overlays of a cell)
    gptr: np.ndarray    # (ng + 1,) tetrahedra of group g: gptr[g]:gptr[g + 1]
    gnodes: np.ndarray  # nodes of the group's cell (crack band width) ...
    gnptr: np.ndarray   # ... gnodes[gnptr[g]:gnptr[g + 1]]
    par: np.ndarray     # (nt, N_ZP, S) law parameters
    state: np.ndarray   # (nt, N_ZS, S) law state
    stress: np.ndarray  # (nt, 6, S)


class Cells(NamedTuple):
    """Elastic hexahedral cells computed as linear (elements.py): cell c
    adds f = -scale[c] K[kind[c]] u over its corners nodes[c] (corner
    i + 2 j + 4 k at offset (i, j, k); degree of freedom 3 corner + d)."""
    nodes: np.ndarray   # (nc, 8)
    kind: np.ndarray    # (nc,)
    scale: np.ndarray   # (nc, S) the cell's Young's modulus
    K: np.ndarray       # (nk, 24, 24) per cell shape, for E = 1


class Contacts(NamedTuple):
    """Sub-contacts (joints, or the strips' bearings).  Sub-contact s joins
    side A and side B at one point: on deformable blocks interpolated from
    nodes[s, 0:cnt[s, 0]] (A) and nodes[s, 4:4 + cnt[s, 1]] (B) with the
    weights w[s] (unused slots: node 0, weight 0); on rigid blocks bodies
    body[s] with body-frame levers lever[s] from their reference points.
    axes[s] = (n, t1, t2), n from A to B.

    Deformable blocks gather the sub-contacts' forces per node (CSR, in
    sub-contact order): node i takes gw[j] force[gs[j]] for j in
    gptr[i]:gptr[i + 1], gw the interpolation weight, negative on side B
    (``contacts.with_gather``).  axes, par, state and force are
    Fortran-ordered, a column per quantity (``contacts.SubContacts.pack``):
    the law's loop over them compiles to vector code.  par, state and
    force hold a row per sub-contact and lane (row s S + b)."""
    nodes: np.ndarray   # (n, 8)
    cnt: np.ndarray     # (n, 2)
    w: np.ndarray       # (n, 8)
    body: np.ndarray    # (n, 2)    rigid blocks (else empty)
    lever: np.ndarray   # (n, 2, 3) rigid blocks (else empty)
    axes: np.ndarray    # (n, 9)
    area: np.ndarray    # (n,)
    par: np.ndarray     # (n S, N_JP) law parameters
    state: np.ndarray   # (n S, N_JS) tractions and law state
    force: np.ndarray   # (n S, 3) work space: each sub-contact's force on side A
    gptr: np.ndarray    # (nodes + 1,) deformable blocks: the per-node gather (else (1,))
    gs: np.ndarray      # sub-contacts ...
    gw: np.ndarray      # ... and their signed weights


CONTACTS_FORTRAN = ("axes", "par", "state", "force")     # the Contacts fields that are Fortran-ordered


class Bodies(NamedTuple):
    """Rotations of rigid bodies (rows as Nodes) and their point loads."""
    R: np.ndarray           # (n, 3, 3, S) orientation, body to global
    om: np.ndarray          # (n, 3, S) angular velocity (global axes)
    mom: np.ndarray         # (n, 3, S) moment of the last step
    iinv: np.ndarray        # (n, 3, 3, S) inverse inertia (body frame)
    rfixed: np.ndarray      # (n, 3) uint8: rotation component prescribed
    ompres: np.ndarray      # (n, 3, S) prescribed angular velocity
    rlen: np.ndarray        # (n,) lever scale (half the diagonal) for the force ratio
    fl: np.ndarray          # (n, 3, S) point loads summed per body, this step
    load_body: np.ndarray   # (k,) point load k acts on this body ...
    load_lever: np.ndarray  # (k, 3) ... at this body-frame lever ...
    load_force: np.ndarray  # (k, 3, S) ... with this force (times the load factor)


class Monitors(NamedTuple):
    """Monitored components: node (or body) nodes[k], component dof[k],
    summed into monitor group group[k]."""
    nodes: np.ndarray
    dof: np.ndarray
    group: np.ndarray


class Scratch(NamedTuple):
    """Work space of the kernels (the zone kernel runs lane by lane and
    shares its part)."""
    de: np.ndarray       # (group size, 6) strain increments of a group
    ev: np.ndarray       # (group size,) their volumetric parts
    pending: np.ndarray  # (nt, 2) zones that may yield: (tetrahedron, group)
    a: np.ndarray        # (3, 3) eigenvalues (diagonal)
    evec: np.ndarray     # (3, 3) eigenvectors (columns)
    U: np.ndarray        # (nc, 24) a run's cells' corner displacements, a row per cell (a batch of one) ...
    F: np.ndarray        # (nk, nc, 24) ... times each kind's matrix (a batch of more lanes: empty, lanes.py)
    sums: np.ndarray     # (4, S) per lane: sum |F| free, sum |applied|, kinetic energy, work rate
    vf: np.ndarray       # (S,) per lane: the velocity factor of the step


class Controls(NamedTuple):
    """Of one call of the step kernel: per lane, where it stands in its
    chunk of steps (a lane's chunk may take several calls; its values do
    not depend on where the calls split it)."""
    step0: np.ndarray   # (S,) int64: the lane's steps before its chunk (history step numbers)
    k0: np.ndarray      # (S,) int64: the steps of its chunk done before this call
    dt: np.ndarray      # (S,)
    lf: np.ndarray      # (S,) load factor (applied forces)
    vf0: np.ndarray     # (S,) velocity factor before the chunk ...
    dvf: np.ndarray     # (S,) ... and its increment per step (a ramp, capped at 1)
    alpha: np.ndarray   # (S,) local damping
    gravity: np.ndarray  # (3,)


def empty_zones():
    z = np.zeros
    return Zones(z((0, 4), np.int64), z((0, 9)), z(0), z(0), z(1, np.int64), z(0, np.int64), z(1, np.int64),
                 z((0, N_ZP)), z((0, N_ZS)), z((0, 6)))


def empty_cells():
    z = np.zeros
    return Cells(z((0, 8), np.int64), z(0, np.int64), z(0), z((0, 24, 24)))


def empty_bodies():
    z = np.zeros
    return Bodies(z((0, 3, 3)), z((0, 3)), z((0, 3)), z((0, 3, 3)), z((0, 3), np.uint8), z((0, 3)), z(0),
                  z((0, 3)), z(0, np.int64), z((0, 3)), z((0, 3)))


# What each container has per lane: field -> the axis of the lane-free
# array (the assembly's, one run's) that stays where it is; the lane axis
# is appended after the array's axes (the sub-contacts': see Contacts).
PER_LANE = {
    "Nodes": ("u", "v", "f", "mass", "mgrav", "vpres", "fext"),
    "Zones": ("par", "state", "stress"),
    "Cells": ("scale",),
    "Contacts": ("par", "state", "force"),
    "Bodies": ("R", "om", "mom", "iinv", "ompres", "fl", "load_force"),
}
