"""The report's parts, in the order of the seed's "Démarche d'application", one module per part.

* `statement` — the statement (Énoncé: bodies, frames, parameters, loads, constraints), step 1
  (the principal constraints, classified) and step 2 (the principal parameters);
* `kinematics` — step 3 (rotation chain, Ω, inertia, the virtual velocity field) and step 4
  (T(Σ/R0) and U_P(Σ/R0) with their formulas);
* `forces` — step 5 (the generalized forces Q_i, load by load, by virtual power);
* `equations` — step 6 (the n Lagrange equations), step 7 (the complementary equations) and
  the first integrals;
* `small_motions` — the small motions about an equilibrium (opt-in);
* `extras` — after step 7: the Newton–Euler cross-check, the simulation's figures, the matrix
  form M q̈ = F and the notes.

Each builds sections of the report's `document` from a `build.Context`, in the words of `words`.
"""
