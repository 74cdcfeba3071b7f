"""HTTP layer over :mod:`ephem` (FastAPI). The app object is ``service.app:app``; no science here."""
