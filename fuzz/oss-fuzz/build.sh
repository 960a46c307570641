#!/bin/bash -eu
# OSS-Fuzz / ClusterFuzzLite build script: copy this folder's files into the project's
# oss-fuzz entry (or .clusterfuzzlite/). The base image provides $CC $CXX $CFLAGS $CXXFLAGS
# $LIB_FUZZING_ENGINE $OUT $SRC; the dependencies come from Debian packages (install-deps.sh).
cd "$SRC/qex"
./install-deps.sh
cmake -S . -B build-oss -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER="$CC" -DCMAKE_CXX_COMPILER="$CXX" \
  -DCMAKE_CXX_FLAGS="$CXXFLAGS" -DQEX_BUILD_TESTS=OFF -DQEX_BUILD_CLI=OFF -DQEX_BUILD_FUZZERS=ON \
  -DQEX_LIBFUZZER=ON
cmake --build build-oss --target fuzzers
for t in fuzz_obj fuzz_ply fuzz_extract fuzz_extract_large fuzz_sanitize fuzz_predicates_differential fuzz_layout; do
  cp "build-oss/fuzz/$t" "$OUT/"
  corpus=${t%_large} # fuzz_extract_large shares fuzz_extract's corpus
  (cd "corpus/$corpus" && zip -qr "$OUT/${t}_seed_corpus.zip" .)
done
cp fuzz/obj.dict "$OUT/fuzz_obj.dict" # libFuzzer dictionaries, found by the target's name
cp fuzz/ply.dict "$OUT/fuzz_ply.dict"
