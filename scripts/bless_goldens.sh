#!/usr/bin/env bash
# Re-blesses the golden images in tests/golden/ after an intended change to the renderer: renders
# every golden frame again and overwrites the PNGs. Check `git diff --stat tests/golden` and look
# at the new images before committing them.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$(nproc)" --target ecpsim_render_tests
ECPSIM_BLESS=1 "$build/tests/ecpsim_render_tests" --gtest_filter='RendererGolden.*'
echo "bless_goldens: rewrote $(ls tests/golden/*.png | wc -l) images in tests/golden/"
