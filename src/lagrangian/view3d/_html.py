"""The 3-D page's former, private name: use `lagrangian.view3d.html`.

Kept only while modules being moved elsewhere still import it (the import contract's
``PENDING`` list, tests/test_import_contract.py); remove it with the last of them.
"""

from .html import CSP, fragment, library

__all__ = ["CSP", "fragment", "library"]
