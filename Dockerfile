# Penumbra on Debian 12: the same packages and steps as README.md's first command.
FROM debian:12
WORKDIR /penumbra
COPY . .
RUN bash .ci/install-deps \
 && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPENUMBRA_TESTS=OFF \
 && cmake --build build -j"$(nproc)"
# The README's first command; 0.0.0.0 only inside the container (publish with -p 8080:8080), which
# needs a token: $PENUMBRA_TOKEN, else a random one (the printed URL carries it).
EXPOSE 8080
CMD ["sh", "-c", "exec build/penumbra serve scenes/cubes15.scene.json --host 0.0.0.0 --port 8080 --token \"${PENUMBRA_TOKEN:-$(od -An -N16 -tx1 /dev/urandom | tr -d ' \\n')}\""]
