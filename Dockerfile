# Build stage: compile the release binary.
FROM rust:1-bookworm AS build
WORKDIR /src
COPY Cargo.toml Cargo.lock ./
COPY src ./src
COPY planner ./planner
COPY migrations ./migrations
# the map page is built into the binary
COPY static ./static
RUN cargo build --release --locked --bin coverplan

# Runtime stage: a small Debian with the binary (which carries the map page) and a non-root user.
FROM debian:bookworm-slim
RUN useradd --system --uid 10001 --home-dir /data coverplan \
    && mkdir -p /data && chown coverplan /data
WORKDIR /app
COPY --from=build /src/target/release/coverplan /usr/local/bin/coverplan
# on a network the server must not run open: it refuses to start until a key exists
# (docker run --rm -v coverplan-data:/data IMAGE keys create --tenant NAME)
ENV COVERPLAN_ADDR=0.0.0.0:8080 \
    COVERPLAN_DATABASE_URL=/data/coverplan.db \
    COVERPLAN_REQUIRE_AUTH=true
USER coverplan
VOLUME ["/data"]
EXPOSE 8080
HEALTHCHECK --interval=30s --timeout=5s --start-period=10s --retries=3 \
    CMD ["coverplan", "healthcheck", "--addr", "127.0.0.1:8080"]
STOPSIGNAL SIGTERM
ENTRYPOINT ["coverplan"]
CMD ["serve"]
