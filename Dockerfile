# The wheelpose:latest image that deploy/ (Kubernetes, Slurm) runs: Debian 12, everything
# installed by the README's set-up command, the release binary as `wheelpose` on the PATH, and
# the checkout's data (configs/, share/, web/, models/) at /wheelpose, where the binary looks
# for them (it records its source folder at build time).
#   docker build -t wheelpose:latest .
#   docker tag wheelpose:latest REGISTRY/wheelpose:latest && docker push REGISTRY/wheelpose:latest
FROM debian:12

ENV DEBIAN_FRONTEND=noninteractive
# setup.sh asks apt for what is missing; these two let it (sudo is a no-op as root) and let
# npm reach its registry over TLS.
RUN apt-get update -qq \
    && apt-get install -y -qq --no-install-recommends ca-certificates sudo \
    && rm -rf /var/lib/apt/lists/*

WORKDIR /wheelpose
COPY . /wheelpose
# Tests and benchmarks are not built: the image runs jobs, CI runs the tests.
RUN bash scripts/setup.sh \
    && cmake --preset release -DWHEELPOSE_BUILD_TESTS=OFF -DWHEELPOSE_BUILD_BENCH=OFF \
    && cmake --build --preset release --target wheelpose \
    && ln -s /wheelpose/build/release/wheelpose /usr/local/bin/wheelpose \
    && find build/release -name '*.o' -delete \
    && rm -rf /var/lib/apt/lists/* /root/.npm

ENTRYPOINT ["wheelpose"]
CMD ["--help"]
