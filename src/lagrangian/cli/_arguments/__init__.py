"""Each command's arguments, declared without importing the pipeline.

``lagrangian --help`` and the parsing of every command line need only these modules
(argparse and plain data): a command's work (``cli/_<command>.py``, SymPy, SciPy, the
compiled numerics) is imported when that command runs, by the ``run`` that `command`
makes.  One module per command, named after it, with ``SUMMARY`` (its line in ``--help``)
and ``register(subparsers)``.
"""
