"""harmonav: provably correct robot navigation with the harmonic navigation functions of
Loizou & Rimon, ``Θ = σ∘φ_k∘Φ``, computed in Rust (the extension module
``harmonav.harmonav``, whose every name is re-exported here) with NumPy arrays in and out.

``harmonav.experiment`` runs declarative studies (TOML specs) on every local core or on a Ray
cluster, with Parquet records (docs/experiments.md)."""

# NumPy first: the extension returns NumPy arrays and loads NumPy's C API lazily, from inside
# Rust, at the first array it makes. A NumPy that cannot be imported must fail here, as an
# ImportError at `import harmonav`, not later as a Rust panic (PanicException).
import numpy as _numpy  # noqa: F401

from .harmonav import *  # noqa: F401,F403  (the extension's names are the package's)
from .harmonav import __version__  # noqa: F401
