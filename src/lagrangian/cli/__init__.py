"""Stage 9 — the command line (`lagrangian derive ...`)."""
