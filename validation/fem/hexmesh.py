"""Structured meshes of 20-node quadratic hexahedra (CalculiX C3D20 / C3D20R) for the reference cases.

A block is a box of elements in a parameter space (a, b, c) mapped to space by a function; every node,
corner or mid-edge, is placed by that map, so curved walls are curved in the elements too. Blocks are
merged into one Mesh by node coordinates (shared faces share nodes). Lengths are in the unit of the map
(the decks use mm).
"""
import numpy as np

# Node order of CalculiX's C3D20 in the element's (xi, eta, zeta) index cube {0, 1, 2}^3: corners 1-8, then
# the mid-edge nodes 9-12 (bottom face), 13-16 (top face), 17-20 (vertical edges).
C3D20_LOCAL = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2),
               (1, 0, 0), (2, 1, 0), (1, 2, 0), (0, 1, 0), (1, 0, 2), (2, 1, 2), (1, 2, 2), (0, 1, 2),
               (0, 0, 1), (2, 0, 1), (2, 2, 1), (0, 2, 1)]
# Faces of C3D20 as CalculiX labels them (positions in C3D20_LOCAL of the 4 corners and 4 mid-edge nodes).
FACES = {"S1": [0, 1, 2, 3, 8, 9, 10, 11], "S2": [4, 7, 6, 5, 15, 14, 13, 12],
         "S3": [0, 4, 5, 1, 16, 12, 17, 8], "S4": [1, 5, 6, 2, 17, 13, 18, 9],
         "S5": [2, 6, 7, 3, 18, 14, 19, 10], "S6": [3, 7, 4, 0, 19, 15, 16, 11]}
# Mirroring an element in xi maps local node k to MIRROR_XI[k] (used to turn left-handed blocks around).
MIRROR_XI = [1, 0, 3, 2, 5, 4, 7, 6, 8, 11, 10, 9, 12, 15, 14, 13, 17, 16, 19, 18]
_OFFSETS = [(i, j, k) for i in (0, -1, 1) for j in (0, -1, 1) for k in (0, -1, 1)]


def graded(x0, x1, n, first=None):
    """n + 1 breakpoints from x0 to x1: uniform, or geometric with the first interval of length |first|
    at x0 (x1 may lie below x0)."""
    length = abs(x1 - x0)
    if first is None or n == 1 or abs(abs(first) * n - length) < 1e-12 * length:
        return list(np.linspace(x0, x1, n + 1))
    first = abs(first)
    # Solve first * (q^n - 1) / (q - 1) = length for the growth ratio q by bisection.
    lo, hi = (1.0 + 1e-12, 10.0) if first * n < length else (1e-3, 1.0 - 1e-12)
    for _ in range(200):
        q = 0.5 * (lo + hi)
        total = first * (q ** n - 1.0) / (q - 1.0)
        if total < length:
            lo = q
        else:
            hi = q
    steps = first * q ** np.arange(n)
    steps *= length / steps.sum()
    return list(x0 + np.sign(x1 - x0) * np.concatenate([[0.0], np.cumsum(steps)]))


def power_graded(x0, x1, n, beta):
    """n + 1 breakpoints x0 + (x1 - x0) t^beta at t = i/n: fine at x0 for beta > 1 (algebraic grading
    towards a singular point at x0; every level of a refinement sequence maps its own uniform t grid through
    the same function, so the sequence stays systematic)."""
    t = np.arange(n + 1) / n
    return list(x0 + (x1 - x0) * t ** beta)


def refine(breaks, m):
    """Every interval of `breaks` split into m equal parts (systematic refinement of a base mesh)."""
    out = [breaks[0]]
    for a, b in zip(breaks[:-1], breaks[1:]):
        out += list(a + (b - a) * np.arange(1, m + 1) / m)
    return out


def _midpoints(breaks):
    """Parameter values of the node lines: breakpoints and the midpoints between them."""
    p = np.empty(2 * len(breaks) - 1)
    p[0::2] = breaks
    p[1::2] = 0.5 * (np.asarray(breaks[:-1]) + np.asarray(breaks[1:]))
    return p


class Mesh:
    """Nodes (1-based ids), C3D20 elements, and the parameter coordinates each node was made from."""

    def __init__(self, tolerance=1e-9):
        self.xyz = []        # node coordinates, id - 1
        self.param = []      # (block name, a, b, c) of the node's first creator
        self.elements = []   # lists of 20 node ids
        self.element_block = []
        self._index = {}
        self._tol = tolerance

    def _node(self, x, tag):
        """The id of the node at x in the same block (tag[0]), created if there is none within the tolerance.
        Blocks of different names never share nodes (a tool touching the wall stays a separate body)."""
        cell = tuple(int(v) for v in np.floor(np.asarray(x) / self._tol))
        for off in _OFFSETS:
            nid = self._index.get((tag[0], cell[0] + off[0], cell[1] + off[1], cell[2] + off[2]))
            if nid is not None and np.linalg.norm(self.xyz[nid - 1] - x) <= self._tol:
                return nid
        self.xyz.append(np.asarray(x, dtype=float))
        self.param.append(tag)
        nid = len(self.xyz)
        self._index[(tag[0],) + cell] = nid
        return nid

    def add_node(self, x, block):
        """A free node (e.g. a rigid body's reference node), never merged."""
        self.xyz.append(np.asarray(x, dtype=float))
        self.param.append((block, 0.0, 0.0, 0.0))
        return len(self.xyz)

    def add_block(self, name, a_breaks, b_breaks, c_breaks, mapping):
        """Adds the elements over the breakpoint grid; mapping(a, b, c) -> (x, y, z). Elements whose map is
        left-handed are mirrored so that every element has a positive Jacobian."""
        pa, pb, pc = _midpoints(a_breaks), _midpoints(b_breaks), _midpoints(c_breaks)
        ids = {}
        for i in range(len(pa)):
            for j in range(len(pb)):
                for k in range(len(pc)):
                    if (i % 2) + (j % 2) + (k % 2) <= 1:
                        ids[(i, j, k)] = self._node(mapping(pa[i], pb[j], pc[k]), (name, pa[i], pb[j], pc[k]))
        for ei in range(len(a_breaks) - 1):
            for ej in range(len(b_breaks) - 1):
                for ek in range(len(c_breaks) - 1):
                    conn = [ids[(2 * ei + u, 2 * ej + v, 2 * ek + w)] for (u, v, w) in C3D20_LOCAL]
                    if self._jacobian_sign(conn) < 0:
                        conn = [conn[MIRROR_XI[n]] for n in range(20)]
                    self.elements.append(conn)
                    self.element_block.append(name)

    def _jacobian_sign(self, conn):
        x = [self.xyz[n - 1] for n in conn[:8]]
        e1 = (x[1] + x[2] + x[5] + x[6]) - (x[0] + x[3] + x[4] + x[7])
        e2 = (x[2] + x[3] + x[6] + x[7]) - (x[0] + x[1] + x[4] + x[5])
        e3 = (x[4] + x[5] + x[6] + x[7]) - (x[0] + x[1] + x[2] + x[3])
        return np.sign(np.dot(np.cross(e1, e2), e3))

    def nodes_where(self, predicate):
        """Ids of the nodes whose coordinates satisfy predicate(xyz)."""
        return [n + 1 for n, x in enumerate(self.xyz) if predicate(x)]

    def nodes_where_param(self, predicate, blocks=None):
        """Ids of the nodes whose parameters satisfy predicate(a, b, c) (optionally only in some blocks)."""
        return [n + 1 for n, (blk, a, b, c) in enumerate(self.param)
                if (blocks is None or blk in blocks) and predicate(a, b, c)]

    def faces_where(self, predicate, blocks=None):
        """(element id, face label) of every element face whose 8 nodes all satisfy predicate(xyz)."""
        return self._faces(lambda n: predicate(self.xyz[n - 1]), blocks)

    def faces_where_param(self, predicate, blocks=None):
        """(element id, face label) of every face whose 8 nodes' parameters satisfy predicate(a, b, c)."""
        return self._faces(lambda n: predicate(*self.param[n - 1][1:]), blocks)

    def _faces(self, node_ok, blocks):
        out = []
        for e, conn in enumerate(self.elements):
            if blocks is not None and self.element_block[e] not in blocks:
                continue
            for label, local in FACES.items():
                if all(node_ok(conn[k]) for k in local):
                    out.append((e + 1, label))
        return out

    def face_weights(self, faces):
        """Per node, the integral of its shape function over the given faces (consistent nodal areas):
        a uniform traction t on the faces is the nodal force t * weight."""
        w = {}
        gauss = [(-np.sqrt(0.6), 5 / 9), (0.0, 8 / 9), (np.sqrt(0.6), 5 / 9)]
        for e, label in faces:
            nodes = [self.elements[e - 1][k] for k in FACES[label]]
            x = np.array([self.xyz[n - 1] for n in nodes])
            for u, wu in gauss:
                for v, wv in gauss:
                    n, dn = _serendipity8(u, v)
                    da = np.linalg.norm(np.cross(dn[:, 0] @ x, dn[:, 1] @ x)) * wu * wv
                    for k, node in enumerate(nodes):
                        w[node] = w.get(node, 0.0) + n[k] * da
        return w


def _serendipity8(u, v):
    """Shape functions of the 8-node quadrilateral (corners, then mid-edges 1-2, 2-3, 3-4, 4-1) and their
    derivatives (8 x 2)."""
    cu = np.array([-1, 1, 1, -1])
    cv = np.array([-1, -1, 1, 1])
    n = np.zeros(8)
    dn = np.zeros((8, 2))
    for k in range(4):
        a, b = cu[k], cv[k]
        n[k] = 0.25 * (1 + a * u) * (1 + b * v) * (a * u + b * v - 1)
        dn[k, 0] = 0.25 * a * (1 + b * v) * (2 * a * u + b * v)
        dn[k, 1] = 0.25 * b * (1 + a * u) * (a * u + 2 * b * v)
    mids = [(0, -1), (1, 0), (0, 1), (-1, 0)]
    for k, (a, b) in enumerate(mids):
        if a == 0:
            n[4 + k] = 0.5 * (1 - u * u) * (1 + b * v)
            dn[4 + k] = [-u * (1 + b * v), 0.5 * b * (1 - u * u)]
        else:
            n[4 + k] = 0.5 * (1 + a * u) * (1 - v * v)
            dn[4 + k] = [0.5 * a * (1 - v * v), -v * (1 + a * u)]
    return n, dn
