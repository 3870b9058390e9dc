"""The vector toolkit's former, private name: use `lagrangian.model.vectors`.

Kept only while modules being moved elsewhere still import it (the import contract's
``PENDING`` list, tests/test_import_contract.py); remove it with the last of them.
"""

from .vectors import AXES, as_expr

__all__ = ["AXES", "as_expr"]
