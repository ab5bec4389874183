# Penumbra on Debian 12: the same packages and steps as README.md's first command.
FROM debian:12
WORKDIR /penumbra
COPY . .
RUN bash .ci/install-deps \
 && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPENUMBRA_TESTS=OFF \
 && cmake --build build -j"$(nproc)"
CMD ["bash", "-c", "build/penumbra reference scenes/cornell.scene.json --grid 24 --out build/cornell.mesh.json"]
