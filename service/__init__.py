"""HTTP layer over :mod:`ephem` (FastAPI). The app object is ``service.app:app``; no science here.

The service is the ``service`` extra of the distribution (``pip install 'ephem-asteroid-pn[service]'``): without
its packages, importing it says so instead of failing deep inside with a bare ``ModuleNotFoundError``.
"""
import importlib.util as _util

#: the top-level packages of the ``service`` extra that the service's modules import
_NEEDS = ("fastapi", "starlette", "pydantic", "uvicorn", "jinja2", "multipart", "orjson", "markdown_it", "matplotlib")


def _installed(module: str) -> bool:
    try:
        return _util.find_spec(module) is not None
    except (ImportError, ValueError):
        return False


_missing = [m for m in _NEEDS if not _installed(m)]
if _missing:
    raise ImportError(f"the HTTP service needs {', '.join(_missing)}, not installed here: install "
                      "ephem-asteroid-pn[service] (pip install 'ephem-asteroid-pn[service]')", name=_missing[0])
