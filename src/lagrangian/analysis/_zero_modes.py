"""The eigenvalue 0 of a linearized motion ẋ = A x: neutral directions, or secular growth.

A zero eigenvalue is *neutral* when it stands for another steady motion next to the one
linearized about; it is not when the linear motion grows along it like t², t³, ...

**Ignorable coordinates first (the quotient).**  A coordinate whose column of A is zero, once
the other such coordinates are set aside, acts on nothing: a shift of it is another steady
motion to first order (the bicycle's y, then its heading ψ, whose only action is δẏ = v δψ).
Ordering the state as (ignorable, rest), A is block triangular,

    A = [ A_ii  A_ir ]
        [  0    A_rr ],

A_ii nilpotent (the ignorable coordinates drive only one another), and the motion of the rest
is ẋ_r = A_rr x_r, whatever the ignorable coordinates do.

**Then the Jordan structure of 0 in A_rr** decides.  Let 𝒩 be the generalized null space of
A_rr, its Jordan blocks of sizes k_1, k_2, ...; the solution holds t^(k−1)/(k−1)! along a
block of size k:

* every block of size 1 (0 semisimple): each zero direction is a conserved quantity (a
  momentum, a speed): a perturbation along it is another steady motion — neutral;
* a block of size 2 whose image A_rr w lies in the coordinates (a change of momentum makes the
  coordinates drift at a constant rate along a direction in which a shift is another
  equilibrium: two masses joined by a spring, translating together) — neutral drift;
* any other block (size ≥ 3, or an image holding speeds) — *secular growth*: the linearized
  motion grows like t^(k−1) (ẍ = k sin θ/m with θ̈ = 0: a shift of θ makes x grow like t², a
  change of θ̇ like t³).  The linearization is then unstable, although every eigenvalue is on
  the imaginary axis: Lyapunov's first method needs semisimple eigenvalues there.

Numerically: the eigenvalues within `CLUSTER_RTOL` of 0 (a Jordan block of size k perturbed by
rounding ε splits into ε^(1/k)) are moved to the front of a Schur form A_rr = Z T Zᴴ, and the
sizes of the blocks read from the ranks of the powers of that leading block T₁₁:
#{blocks of size ≥ j} = rank T₁₁^(j−1) − rank T₁₁^j (Golub & Van Loan, *Matrix Computations*,
§7.6.5; Kågström & Ruhe, ACM TOMS 6 (1980) 398).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import linalg

__all__ = ["CLUSTER_RTOL", "ZERO_RTOL", "ZeroStructure", "ignorable_columns", "split_off", "zero_structure"]

#: Relative size (to the largest |A| entry) below which an entry of A counts as zero.
ZERO_RTOL = 1e-12
#: Relative size (to the largest |A| entry) below which an eigenvalue counts as 0: a Jordan
#: block of size 2 perturbed by rounding (1e-16) splits into eigenvalues of size 1e-8, of size 3
#: into 5e-6 (structural zeros of A keep them exact in most models).
CLUSTER_RTOL = 1e-6
#: Relative size below which a singular value of a power of the zero block counts as zero.
RANK_RTOL = 1e-8


def _tol(A: np.ndarray) -> float:
    return ZERO_RTOL * max(1.0, float(np.abs(A).max(initial=0.0)))


def ignorable_columns(A: np.ndarray, coordinates: int) -> list[int]:
    """State indices (among the first ``coordinates``) whose column of A is zero once the others found
    are set aside: the bicycle's y first (δẏ = v δψ is its only use of ψ), then its heading ψ."""
    tol = _tol(A)
    keep = list(range(A.shape[0]))
    out: list[int] = []
    changed = True
    while changed:
        changed = False
        for c in range(coordinates):
            if c in keep and not np.any(np.abs(A[np.ix_(keep, [c])]) > tol):
                keep.remove(c)
                out.append(c)
                changed = True
    return sorted(out)


def split_off(A: np.ndarray, keep: Sequence[int]) -> tuple[list[int], list[tuple[int, str]]]:
    """Variables of ``keep`` whose row (conserved to first order) or column (acting on none of the
    others) is zero within ``keep``, split off repeatedly, each with eigenvalue 0: (what is left, the
    variables split off with "row" or "column")."""
    tol = _tol(A)
    keep = list(keep)
    out: list[tuple[int, str]] = []
    changed = True
    while changed:
        changed = False
        for i in list(keep):
            sub = A[np.ix_(keep, keep)]
            k = keep.index(i)
            if not np.any(np.abs(sub[:, k]) > tol):
                out.append((i, "column"))
            elif not np.any(np.abs(sub[k, :]) > tol):
                out.append((i, "row"))
            else:
                continue
            keep.remove(i)
            changed = True
    return keep, out


@dataclass(frozen=True, slots=True)
class ZeroStructure:
    """The eigenvalue 0 of A once the ignorable coordinates are set aside.

    ``blocks``: the sizes of its Jordan blocks; ``secular``: whether the linearized motion grows
    (a block of size ≥ 3, or of size 2 whose image holds speeds); then ``start`` and ``end`` name
    the state variables of the longest chain (a perturbation of ``start`` makes ``end`` grow), and
    ``growth`` is the power of t with which the whole state grows (ignorable coordinates included).
    """

    blocks: tuple[int, ...]
    secular: bool
    growth: int = 0
    start: str | None = None
    end: str | None = None


def _zero_block(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(T₁₁, Z₁): the Schur block of the eigenvalues near 0 and its orthonormal basis (A Z₁ = Z₁ T₁₁)."""
    n = A.shape[0]
    if n == 0:
        return np.zeros((0, 0)), np.zeros((0, 0))
    scale = max(1.0, float(np.abs(A).max(initial=0.0)))
    T, Z, k = linalg.schur(A.astype(complex), output="complex", sort=lambda z: abs(z) <= CLUSTER_RTOL * scale)
    return T[:k, :k], Z[:, :k]


def _rank(X: np.ndarray, scale: float) -> int:
    if X.size == 0:
        return 0
    s = np.linalg.svd(X, compute_uv=False)
    return int(np.count_nonzero(s > RANK_RTOL * scale))


def _blocks(T: np.ndarray, scale: float) -> tuple[list[int], list[np.ndarray]]:
    """Jordan block sizes of the nilpotent T (descending), and its powers T⁰, T¹, ..."""
    k = T.shape[0]
    powers = [np.eye(k, dtype=complex)]
    ranks = [k]
    while ranks[-1] > 0 and len(ranks) <= k:
        powers.append(powers[-1] @ T)
        ranks.append(_rank(powers[-1], scale ** (len(powers) - 1)))
        if ranks[-1] == ranks[-2]:
            break
    at_least = [ranks[j - 1] - ranks[j] for j in range(1, len(ranks))]  # blocks of size ≥ j
    sizes: list[int] = []
    for j in range(len(at_least), 0, -1):
        exactly = at_least[j - 1] - (at_least[j] if j < len(at_least) else 0)
        sizes += [j] * exactly
    return sizes, powers


def _longest_chain(A: np.ndarray, names: Sequence[str]) -> tuple[int, str | None, str | None]:
    """(L, start, end): the longest Jordan chain of 0 in A, the variable that starts it and the one it
    grows in (the largest components of v and of A^(L−1) v)."""
    scale = max(1.0, float(np.abs(A).max(initial=0.0)))
    T, Z = _zero_block(A)
    if T.size == 0:
        return 0, None, None
    sizes, powers = _blocks(T, scale)
    L = max(sizes, default=1)
    P = powers[L - 1] if L - 1 < len(powers) else np.linalg.matrix_power(T, L - 1)
    _, _, vh = np.linalg.svd(P)
    v = vh[0].conj()  # the direction P stretches most
    start = Z @ v
    end = Z @ (P @ v)
    return L, names[int(np.argmax(np.abs(start)))], names[int(np.argmax(np.abs(end)))]


def zero_structure(A: np.ndarray, state: Sequence[str], coordinates: int) -> ZeroStructure:
    """The Jordan structure of 0 in A once the ignorable coordinates (the first ``coordinates`` state
    variables are coordinates) are set aside, and whether it makes the linearized motion grow."""
    ign = ignorable_columns(A, coordinates)
    rest = [i for i in range(A.shape[0]) if i not in ign]
    Arr = A[np.ix_(rest, rest)]
    scale = max(1.0, float(np.abs(A).max(initial=0.0)))
    T, Z = _zero_block(Arr)
    if T.size == 0:
        return ZeroStructure((), False)
    sizes, _ = _blocks(T, scale)
    secular = any(s >= 3 for s in sizes)
    if not secular and 2 in sizes:
        # With no block longer than 2, A_rr maps 𝒩 = range(Z₁) onto the bottoms of the chains, range(Z₁ T₁₁):
        # they must lie in the coordinates (a drift), not hold speeds.
        image = Z @ T
        speeds = [j for j, i in enumerate(rest) if i >= coordinates]
        secular = float(np.abs(image[speeds]).max(initial=0.0)) > 1e-6 * max(1.0, float(np.abs(image).max(initial=0.0)))
    if not secular:
        return ZeroStructure(tuple(sizes), False)
    L, start, end = _longest_chain(A, state)  # on the whole state: the ignorable coordinates grow too
    chain_rr, start_rr, _ = _longest_chain(Arr, [state[i] for i in rest])
    return ZeroStructure(tuple(sizes), True, max(L, chain_rr) - 1, start_rr or start, end)
