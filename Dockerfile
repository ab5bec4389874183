# Penumbra on Debian 12: the same packages and steps as README.md's first command.
FROM debian:12
WORKDIR /penumbra
COPY . .
RUN bash .ci/install-deps \
 && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPENUMBRA_TESTS=OFF \
 && cmake --build build -j"$(nproc)"
# The README's first command; 0.0.0.0 only inside the container (publish with -p 8080:8080).
EXPOSE 8080
CMD ["build/penumbra", "serve", "scenes/cubes15.scene.json", "--host", "0.0.0.0", "--port", "8080"]
