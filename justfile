# Recipes for hypercontact. Each is also a plain cargo command (see README).

# Rerun the paper end to end on the embedded default data.
paper:
    cargo run --release -- run pipelines/paper.yaml

# The small end-to-end pipeline used by the tests.
quick:
    cargo run --release -- run pipelines/quick.yaml

# All tests, as CI runs them.
test:
    cargo test --workspace --release

# Benchmarks of every stage (criterion).
bench:
    cargo bench --workspace

# Formatting and lints, as CI checks them.
lint:
    cargo fmt --all -- --check
    cargo clippy --workspace --all-targets --release -- -D warnings

# Describe every stage kind.
stages:
    cargo run --release -- stages
