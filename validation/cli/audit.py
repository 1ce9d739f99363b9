"""``prbm-validate audit``: plant errors in each method and count the cases that catch them."""

from __future__ import annotations

from validation.stress.audit import cmd_audit


def run(args) -> int:
    return cmd_audit(args)
