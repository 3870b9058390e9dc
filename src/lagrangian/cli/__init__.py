"""Stage 8 — the command line (`lagrangian derive ...`)."""
