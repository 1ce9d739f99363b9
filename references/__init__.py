"""The bibliography: each cited document's key and full citation (``references.bibliography``).

A leaf package: it imports nothing of the project, so every package may import it.
"""

from references.bibliography import REFERENCES, Reference, citation, key_of_seed_file

__all__ = ["REFERENCES", "Reference", "citation", "key_of_seed_file"]
