"""Greek letters by name, as the course writes them: ``psi`` → ψ, ``theta1`` → θ1, ``phi`` → φ.

One table for every printer: the terminal and LaTeX notation (`lagrangian.output._notation`) and
the labels of the 3-D view (`lagrangian.view3d`).
"""

from __future__ import annotations

__all__ = ["GREEK", "greek_text"]

#: name → (text, LaTeX).
GREEK = {
    "alpha": ("α", r"\alpha"), "beta": ("β", r"\beta"), "gamma": ("γ", r"\gamma"), "delta": ("δ", r"\delta"),
    "epsilon": ("ε", r"\varepsilon"), "eps": ("ε", r"\varepsilon"), "zeta": ("ζ", r"\zeta"), "eta": ("η", r"\eta"), "theta": ("θ", r"\theta"),
    "iota": ("ι", r"\iota"), "kappa": ("κ", r"\kappa"), "lambda": ("λ", r"\lambda"), "lam": ("λ", r"\lambda"),
    "mu": ("μ", r"\mu"), "nu": ("ν", r"\nu"), "xi": ("ξ", r"\xi"), "rho": ("ρ", r"\rho"),
    "sigma": ("σ", r"\sigma"), "tau": ("τ", r"\tau"), "phi": ("φ", r"\varphi"), "chi": ("χ", r"\chi"),
    "psi": ("ψ", r"\psi"), "omega": ("ω", r"\omega"), "Gamma": ("Γ", r"\Gamma"), "Delta": ("Δ", r"\Delta"),
    "Theta": ("Θ", r"\Theta"), "Lambda": ("Λ", r"\Lambda"), "Xi": ("Ξ", r"\Xi"), "Pi": ("Π", r"\Pi"),
    "Sigma": ("Σ", r"\Sigma"), "Phi": ("Φ", r"\Phi"), "Psi": ("Ψ", r"\Psi"), "Omega": ("Ω", r"\Omega"),
}


def greek_text(name: str) -> str:
    """``psi`` → ``ψ``, ``theta1`` → ``θ1``, ``thetaB`` → ``θB``; any other name as it is.

    The index after a Greek name is digits or starts with a capital (``thetas`` is a word).
    """
    if name in GREEK:
        return GREEK[name][0]
    for head in sorted(GREEK, key=len, reverse=True):
        tail = name[len(head):]
        if name.startswith(head) and tail and tail.isalnum() and (tail.isdigit() or tail[0].isupper()):
            return GREEK[head][0] + tail
    return name
