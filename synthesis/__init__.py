"""Synthesis of compliant mechanisms with the PRBM, verified with the FEM (seed 000 chapters 3, 5, 6, 7)."""
from synthesis.cli import add_parser, synthesize
from synthesis.design import Design, compare_printed, design
from synthesis.dyads import FourBar, SliderCrank, SynthesisError
from synthesis.spec import Spec, SpecError, load_spec

__all__ = ["add_parser", "synthesize", "Design", "compare_printed", "design", "FourBar", "SliderCrank",
           "SynthesisError", "Spec", "SpecError", "load_spec"]
