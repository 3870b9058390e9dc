"""Stage 6 — the command line (`lagrangian derive ...`)."""
