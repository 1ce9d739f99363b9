"""``prbm-validate synthesize``: design from a specification, write it, check it with the FEM."""

from __future__ import annotations

from validation.synthesis.synthesize import synthesize


def run(args) -> int:
    return synthesize(args.spec, args.out, run_fem=False if args.no_fem else None)
