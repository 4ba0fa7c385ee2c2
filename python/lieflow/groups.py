"""SO(3) and SE(3), vectorized: one object holds N group elements.

Conventions are lieflow's (README "Conventions"): Hamilton quaternions
(w, x, y, z); R maps body vectors to world vectors; SE(3) tangents are
(rho, omega), translation first; perturbations on the right, X (+) d =
X exp(d); Jr is the right Jacobian of exp, Jl(w) = Jr(-w).

Every number comes from lieflow's C++ SO3<double>/SE3<double> applied row by
row in the extension module (bit for bit the C++ results), without a Python
loop. Arrays of shape (N, k) give N elements; a single (k,) gives one, and
results then drop the leading axis.

    R = lieflow.SO3.exp(np.random.randn(1000, 3))   # 1000 rotations
    w = R.log()                                      # (1000, 3)
    p = R.act(np.array([1.0, 0.0, 0.0]))             # (1000, 3): one point, each rotation
    M = (R * R.inverse()).matrix()                   # (1000, 3, 3), identities
"""
import numbers

import numpy as np

from . import _lieflow
from ._lieflow import InputError


def _float_array(array, what):
    """`array` as float64 (InputError naming `what` for None, text, objects,
    complex numbers); the C++ kernels check each entry's value."""
    if array is None:
        raise InputError(f"{what}: expected numbers, got None")
    if isinstance(array, (str, bytes)):
        raise InputError(f"{what}: expected numbers, got {array!r}")
    try:
        a = np.asarray(array)
        if a.dtype.kind not in "biuf":
            raise TypeError(f"{a.dtype} entries")
        return np.asarray(a, dtype=np.float64)
    except (TypeError, ValueError, OverflowError) as e:
        raise InputError(f"{what}: expected an array of real numbers ({e})") from None


def _as_rows(array, k, what):
    """(rows as an (N, k) float64 array, whether the input was a single (k,))."""
    a = _float_array(array, what)
    if a.ndim == 1 and a.shape[0] == k:
        return a.reshape(1, k), True
    if a.ndim == 2 and a.shape[1] == k:
        return np.ascontiguousarray(a), False
    raise InputError(f"{what}: expected shape ({k},) or (N, {k}), got {a.shape}")


def _matrices(array, n, what):
    a = _float_array(array, what)
    if a.shape == (n, n):
        return a.reshape(1, n * n), True
    if a.ndim == 3 and a.shape[1:] == (n, n):
        return np.ascontiguousarray(a.reshape(a.shape[0], n * n)), False
    raise InputError(f"{what}: expected shape ({n}, {n}) or (N, {n}, {n}), got {a.shape}")


def _shape(out, single, *tail):
    out = out.reshape((out.shape[0],) + tail) if tail else out
    return out[0] if single else out


# Most elements SO3.identity(n) / SE3.identity(n) makes at once.
_MAX_ELEMENTS = 10_000_000
# The defaults of SO3() and SE3() (None is refused, not read as the identity).
_IDENTITY_QUATERNION = (1.0, 0.0, 0.0, 0.0)
_ZERO_TRANSLATION = (0.0, 0.0, 0.0)


class _Group:
    """Shared behaviour of SO3 and SE3: N elements stored as the rows of an
    (N, 4) (SO3: quaternions) or (N, 7) (SE3: quaternion, translation) array."""

    _DOF = 0
    _PREFIX = ""

    def __init__(self, rows, single):
        self._rows = rows
        self._single = single

    @classmethod
    def _make(cls, rows, single):
        return cls(rows, single)

    @classmethod
    def _kernel(cls, name):
        return getattr(_lieflow, cls._PREFIX + name)

    @classmethod
    def exp(cls, tangent):
        """exp of tangents of shape (DoF,) or (N, DoF)."""
        t, single = _as_rows(tangent, cls._DOF, f"{cls.__name__}.exp: tangent")
        return cls._make(cls._kernel("exp")(t), single)

    @classmethod
    def identity(cls, n=None):
        """The identity (n=None) or n identities."""
        if n is not None and (isinstance(n, bool) or not isinstance(n, numbers.Integral) or not 0 <= n <= _MAX_ELEMENTS):
            raise InputError(f"{cls.__name__}.identity: n must be None or an integer in [0, {_MAX_ELEMENTS}], got {n!r}")
        t = np.zeros((1 if n is None else int(n), cls._DOF))
        return cls._make(cls._kernel("exp")(t), n is None)

    def log(self):
        return _shape(self._kernel("log")(self._rows), self._single)

    def inverse(self):
        return self._make(self._kernel("inverse")(self._rows), self._single)

    def compose(self, other):
        """self * other, element by element (a single element pairs with all)."""
        if not isinstance(other, type(self)):
            raise InputError(f"{type(self).__name__}.compose: expected a {type(self).__name__}, got {type(other).__name__}")
        return self._make(self._kernel("compose")(self._rows, other._rows), self._single and other._single)

    def act(self, points):
        """R p (or R p + t): points of shape (3,) or (N, 3)."""
        p, single = _as_rows(points, 3, f"{type(self).__name__}.act: points")
        return _shape(self._kernel("act")(self._rows, p), self._single and single)

    def __mul__(self, other):
        if isinstance(other, type(self)):
            return self.compose(other)
        if isinstance(other, _Group):
            raise InputError(f"{type(self).__name__} * {type(other).__name__}: compose elements of one group "
                             "(or act on points)")
        return self.act(other)

    def Adj(self):
        return _shape(self._kernel("adj")(self._rows), self._single, self._DOF, self._DOF)

    def quaternion(self):
        """Unit quaternions (w, x, y, z) of the rotations: (4,) or (N, 4)."""
        return _shape(self._rows[:, :4].copy(), self._single)

    @classmethod
    def _jacobian(cls, tangent, which):
        t, single = _as_rows(tangent, cls._DOF, f"{cls.__name__}.{which}: tangent")
        return _shape(cls._kernel("jacobian")(t, which), single, cls._DOF, cls._DOF)

    @classmethod
    def Jr(cls, tangent):
        """Right Jacobian of exp: exp(w + d) ~ exp(w) exp(Jr(w) d)."""
        return cls._jacobian(tangent, "Jr")

    @classmethod
    def Jl(cls, tangent):
        """Left Jacobian of exp, Jl(w) = Jr(-w)."""
        return cls._jacobian(tangent, "Jl")

    @classmethod
    def JrInv(cls, tangent):
        return cls._jacobian(tangent, "JrInv")

    @classmethod
    def JlInv(cls, tangent):
        return cls._jacobian(tangent, "JlInv")

    def __len__(self):
        return self._rows.shape[0]

    def __iter__(self):
        return (self[i] for i in range(len(self)))

    def __getitem__(self, index):
        try:
            rows = self._rows[index]
        except (IndexError, TypeError) as e:
            raise InputError(f"{type(self).__name__}[{index!r}]: {e}") from None
        if rows.ndim == 1:
            return self._make(rows.reshape(1, -1).copy(), True)
        return self._make(np.ascontiguousarray(rows), False)

    def __repr__(self):
        what = "1 element" if self._single else f"{len(self)} elements"
        return f"lieflow.{type(self).__name__}({what})"


class SO3(_Group):
    """Rotations, stored as unit quaternions (w, x, y, z)."""

    _DOF = 3
    _PREFIX = "so3_"

    def __init__(self, quaternion=_IDENTITY_QUATERNION, _rows=None, _single=True):
        if _rows is not None:
            super().__init__(_rows, _single)
            return
        q, single = _as_rows(quaternion, 4, "SO3: quaternion")
        super().__init__(_lieflow.so3_from_quaternion(q), single)

    @classmethod
    def _make(cls, rows, single):
        return cls(_rows=rows, _single=single)

    @classmethod
    def from_quaternion(cls, quaternion):
        """From quaternions (w, x, y, z), (4,) or (N, 4): checked (finite, norm
        within 1e-6 of 1, then normalized), else InputError naming the row."""
        return cls(quaternion)

    @classmethod
    def from_matrix(cls, matrix):
        """From rotation matrices, (3, 3) or (N, 3, 3): checked (orthonormal to
        1e-6, det +1, then projected), else InputError naming the row."""
        m, single = _matrices(matrix, 3, "SO3.from_matrix")
        return cls(_rows=_lieflow.so3_from_matrix(m), _single=single)

    def matrix(self):
        return _shape(_lieflow.so3_matrix(self._rows), self._single, 3, 3)


class SE3(_Group):
    """Rigid motions, stored as (qw, qx, qy, qz, x, y, z)."""

    _DOF = 6
    _PREFIX = "se3_"

    def __init__(self, quaternion=_IDENTITY_QUATERNION, translation=_ZERO_TRANSLATION, _rows=None, _single=True):
        if _rows is not None:
            super().__init__(_rows, _single)
            return
        q, single_q = _as_rows(quaternion, 4, "SE3: quaternion")
        t, single_t = _as_rows(translation, 3, "SE3: translation")
        if q.shape[0] != t.shape[0]:
            if q.shape[0] == 1:
                q = np.repeat(q, t.shape[0], axis=0)
            elif t.shape[0] == 1:
                t = np.repeat(t, q.shape[0], axis=0)
            else:
                raise InputError(f"SE3: {q.shape[0]} quaternions and {t.shape[0]} translations")
        rows = _lieflow.se3_from_quaternion_translation(np.ascontiguousarray(np.hstack([q, t])))
        super().__init__(rows, single_q and single_t)

    @classmethod
    def _make(cls, rows, single):
        return cls(_rows=rows, _single=single)

    @classmethod
    def from_matrix(cls, matrix):
        """From homogeneous matrices, (4, 4) or (N, 4, 4): checked as
        SO3.from_matrix, last row (0, 0, 0, 1)."""
        m, single = _matrices(matrix, 4, "SE3.from_matrix")
        return cls(_rows=_lieflow.se3_from_matrix(m), _single=single)

    def matrix(self):
        return _shape(_lieflow.se3_matrix(self._rows), self._single, 4, 4)

    def rotation(self):
        return SO3(_rows=np.ascontiguousarray(self._rows[:, :4]), _single=self._single)

    def translation(self):
        return _shape(self._rows[:, 4:].copy(), self._single)

