"""Synthesis of compliant mechanisms with the PRBM, verified with the FEM (seed 000 chapters 3, 5, 6, 7)."""
from importlib import import_module

_EXPORTS = {"add_parser": "synthesis.cli", "synthesize": "synthesis.cli", "Design": "synthesis.design",
            "compare_printed": "synthesis.design", "design": "synthesis.design", "FourBar": "synthesis.dyads",
            "SliderCrank": "synthesis.dyads", "SynthesisError": "synthesis.dyads", "Spec": "synthesis.spec",
            "SpecError": "synthesis.spec", "load_spec": "synthesis.spec"}

__all__ = list(_EXPORTS)


def __getattr__(name: str):
    """The public names, imported on first use (PEP 562): ``prbm-validate`` builds its parser, which
    includes ``synthesize``, without loading the synthesis solvers."""
    if name in _EXPORTS:
        module = import_module(_EXPORTS[name])
        for export, home in _EXPORTS.items():   # every name of that module, over the submodule of
            if home == module.__name__:          # the same name (``design``) bound by the import
                globals()[export] = getattr(module, export)
        return globals()[name]
    raise AttributeError(f"module 'synthesis' has no attribute {name!r}")
