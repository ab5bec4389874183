# Penumbra on Debian 12 in two stages (README "Command line": docker build / docker run).
# Build: the packages and steps of README.md's first command (.ci/install-deps: compilers, -dev
# packages, node/npm for three.js; tests off).
FROM debian:12 AS build
WORKDIR /penumbra
COPY . .
RUN bash .ci/install-deps \
 && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPENUMBRA_TESTS=OFF \
 && cmake --build build -j"$(nproc)" --target penumbra penumbra_image web_page

# Runtime: the shared libraries penumbra and its image module load (no compilers, no chromium,
# no test tools, no node), the page (its bundle holds three.js), the bundled scenes; run as an unprivileged user
# whose home holds the journal (./penumbra-data).
FROM debian:12-slim
RUN apt-get update -qq \
 && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      libembree3-3 libtbb12 libtinyobjloader2rc10 libtinygltf2d libcpp-httplib0.11 libsqlite3-0 \
      libopenimageio2.4 libteem2 libjemalloc2 libdraco7 libmeshoptimizer2d \
 && rm -rf /var/lib/apt/lists/* \
 && useradd --system --create-home --home-dir /var/lib/penumbra --shell /usr/sbin/nologin penumbra
# The layout `penumbra serve` looks for: the image module beside the executable, web_client/
# beside its folder.
COPY --from=build /penumbra/build/penumbra /penumbra/build/libpenumbra_image.so /opt/penumbra/bin/
COPY --from=build /penumbra/web_client/index.html /penumbra/web_client/styles.css /opt/penumbra/web_client/
COPY --from=build /penumbra/web_client/src /opt/penumbra/web_client/src
COPY --from=build /penumbra/web_client/dist /opt/penumbra/web_client/dist
COPY --from=build /penumbra/scenes /opt/penumbra/scenes
USER penumbra
WORKDIR /var/lib/penumbra
# 0.0.0.0 only inside the container (publish with -p 8080:8080), which needs a token:
# $PENUMBRA_TOKEN, else a random one (the printed URL carries it).
EXPOSE 8080
CMD ["sh", "-c", "exec /opt/penumbra/bin/penumbra serve /opt/penumbra/scenes/cubes15.scene.json --host 0.0.0.0 --port 8080 --token \"${PENUMBRA_TOKEN:-$(od -An -N16 -tx1 /dev/urandom | tr -d ' \\n')}\""]
