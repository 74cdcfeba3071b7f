"""Service limits, from environment variables (read once when the app is created)."""
from __future__ import annotations

import os
from dataclasses import dataclass


def _int_env(name: str, default: int) -> int:
    raw = os.environ.get(name)
    if raw is None or raw.strip() == "":
        return default
    try:
        value = int(raw)
    except ValueError:
        raise SystemExit(f"{name} must be an integer, got {raw!r}") from None
    if value <= 0:
        raise SystemExit(f"{name} must be positive, got {value}")
    return value


def _bool_env(name: str, default: bool) -> bool:
    raw = os.environ.get(name)
    if raw is None or raw.strip() == "":
        return default
    value = raw.strip().lower()
    if value in ("1", "true", "yes", "on"):
        return True
    if value in ("0", "false", "no", "off"):
        return False
    raise SystemExit(f"{name} must be one of 1/0, true/false, yes/no, on/off; got {raw!r}")


@dataclass(frozen=True)
class Settings:
    #: largest number of epochs in one track (422 beyond)
    max_track_samples: int = 1_000_000
    #: largest request body in bytes (413 beyond)
    max_body_bytes: int = 65_536
    #: build the Earth's lunisolar series at start-up (~2 s) rather than in the first Earth request
    warm_up: bool = True

    @classmethod
    def from_env(cls) -> "Settings":
        return cls(max_track_samples=_int_env("EPHEM_MAX_TRACK_SAMPLES", cls.max_track_samples),
                   max_body_bytes=_int_env("EPHEM_MAX_BODY_BYTES", cls.max_body_bytes),
                   warm_up=_bool_env("EPHEM_WARM_UP", cls.warm_up))
