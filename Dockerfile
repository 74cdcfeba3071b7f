# ephem REST service: `docker build -t ephem .` then `docker run -p 8000:8000 ephem`
# (`-e WORKERS=4` for more worker processes; the limits below can be overridden likewise).
#
# Stage 1 builds the project's wheel (hatchling; the wheel carries data/ as ephem/_data, so the
# installed package needs no EPHEM_DATA_DIR). Stage 2 installs it with every extra (the service, the
# batch engine, the figures, the N-body rung), as `pip install '.[all]'` would, and keeps no source
# tree: the app is imported from site-packages. Both stages install with the
# lock, constraints.txt: pip, the build backend and every dependency at the versions CI tests.

FROM python:3.11-slim AS build
ENV PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1
WORKDIR /src
COPY constraints.txt ./
# pip at the lock's version (not whatever is newest): --build-constraint needs pip >= 25.3
RUN python -m pip install --constraint constraints.txt pip
COPY pyproject.toml README.md ./
COPY ephem ./ephem
COPY service ./service
COPY data ./data
RUN python -m pip wheel --no-deps --build-constraint constraints.txt --wheel-dir /wheels .


FROM python:3.11-slim
ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1

COPY constraints.txt /tmp/constraints.txt
COPY --from=build /wheels /wheels
RUN python -m pip install --constraint /tmp/constraints.txt pip \
    && python -m pip install --constraint /tmp/constraints.txt "$(ls /wheels/*.whl)[all]" \
    && rm -rf /wheels /tmp/constraints.txt \
    && useradd --create-home --uid 10001 --user-group --shell /usr/sbin/nologin ephem

# Number of worker processes under gunicorn (one per core is a good start).
ENV WORKERS=2
# Largest number of epochs in one /track request (422 beyond). Each 10^4 epochs cost ~1.2 MB of
# JSON and ~5 ms of one worker's CPU: 10^5 is 12 MB; at 10^6 one answer held its worker for ~0.3 s
# and stalled the other requests there (benchmarks/RESULTS_load.md). The other limits: README.
ENV EPHEM_MAX_TRACK_SAMPLES=100000
# Largest request body in bytes (413 beyond).
ENV EPHEM_MAX_BODY_BYTES=65536

# the documents the web page links (docs/*.md rendered as HTML, with their charts: service/docs_pages.py); the wheel
# carries only docs/accuracy.md's copy
COPY docs /srv/ephem-docs
ENV EPHEM_DOCS_DIR=/srv/ephem-docs

USER ephem
WORKDIR /home/ephem
EXPOSE 8000

HEALTHCHECK --interval=30s --timeout=5s --start-period=30s --retries=3 \
    CMD ["python", "-c", "import sys, urllib.request; r = urllib.request.urlopen('http://127.0.0.1:8000/healthz', timeout=4); sys.exit(0 if r.status == 200 else 1)"]

# gunicorn supervises uvicorn workers (service/gunicorn_conf.py: worker class, timeouts, memory
# ceiling), restarting one that dies or hangs; the config is read from the installed package.
# exec: gunicorn becomes PID 1 and gets SIGTERM from `docker stop` (it then stops its workers).
CMD ["sh", "-c", "exec gunicorn --config python:service.gunicorn_conf --bind 0.0.0.0:8000 --workers \"${WORKERS:-2}\" service.app:app"]
