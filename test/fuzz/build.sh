#!/usr/bin/env bash
# build.sh [OUT_DIR]: builds every test/fuzz/fuzz_*.c as a libFuzzer target (clang-15,
# -fsanitize=fuzzer,address,undefined) into OUT_DIR (default build-fuzz/), e.g.
#   bash test/fuzz/build.sh && build-fuzz/fuzz_hair -max_total_time=60 test/fuzz/corpus/fuzz_hair
#
# A target names the library sources it needs in a comment line (globs, relative to the repo
# root), which keeps the sanitized build small and fast:
#   /* FUZZ_SOURCES: host/io/hair/*.c host/base/common.c */
# Without that line it links against an archive of every library source of the Makefile
# (host/**/*.c but host/cli/main.c, host/**/*.cpp, cpu/*.c, cpu/reference/*.c; a cold build of all of them
# takes ~25 s of CPU). Sources are compiled with clang-15 / clang++-15
# -fsanitize=fuzzer-no-link,address,undefined (C++ must be clang++: g++ objects do not carry
# the sanitizer coverage hooks); include flags and libraries come from the Makefile itself.
# The build is incremental (a generated makefile with dependency files) and runs 2 jobs.
# Exit status: 0 built, 1 build failure, 3 clang-15 missing.
set -eu
cd "$(dirname "$0")/../.."
OUT=${1:-${FUZZ_BUILD:-build-fuzz}}
CC=${FUZZ_CC:-clang-15}
CXX=${FUZZ_CXX:-clang++-15}
if ! command -v "$CC" >/dev/null 2>&1; then
    echo "build.sh: $CC not found (apt-get install clang-15)" >&2
    exit 3
fi
command -v "$CXX" >/dev/null 2>&1 || CXX=""

# Flags as the main Makefile has them (printed unexpanded, so quoting survives).
mkvar() { make -s --no-print-directory BUILD="$OUT/.none" --eval='print-%: ; @:$(info $($*))' "print-$1"; }
CPPFLAGS=$(mkvar CPPFLAGS)
LDLIBS=$(mkvar LDLIBS)
CXXINC=$(mkvar CXXFLAGS | tr ' ' '\n' | grep '^-I' | tr '\n' ' ' || true)
LIB_ALL=$(find host cpu -name '*.c' -o -name '*.cpp' | sort | grep -v '^host/cli/main\.c$' || true)

mkdir -p "$OUT"
MK="$OUT/fuzz.mk"
SAN="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
{
    echo "CPPFLAGS := $CPPFLAGS"
    echo "CFLAGS := -std=c11 -O1 -g -MMD -MP $SAN"
    echo "CXXFLAGS := -std=c++17 -O1 -g -MMD -MP $SAN $CXXINC"
    echo "LDLIBS := $LDLIBS"
    echo "all:"
    echo "$OUT/obj/%.o: %.c"
    printf '\t@mkdir -p $(@D)\n\t%s $(CPPFLAGS) $(CFLAGS) -c -o $@ $<\n' "$CC"
    echo "$OUT/obj/%.o: %.cpp"
    printf '\t@mkdir -p $(@D)\n\t%s $(CPPFLAGS) $(CXXFLAGS) -c -o $@ $<\n' "${CXX:-false}"
} > "$MK.tmp"

# Every library source goes into one archive, for targets without FUZZ_SOURCES: the linker
# then takes only the objects a target needs.
all_objs=""
for s in $LIB_ALL; do all_objs="$all_objs $OUT/obj/${s%.*}.o"; done
{
    echo "$OUT/libfuzzlib.a: $all_objs"
    printf '	@rm -f $@ && ar rcs $@ $^
'
} >> "$MK.tmp"
# Link with clang++ when there is one: the archive may hold C++ (the OpenEXR shim).
LINK=${CXX:-$CC}
targets=""
for src in test/fuzz/fuzz_*.c; do
    [ -e "$src" ] || continue
    name=$(basename "$src" .c)
    decl=$(sed -n 's|.*FUZZ_SOURCES:\(.*\)\*/.*|\1|p;s|.*FUZZ_SOURCES:\(.*\)$|\1|p' "$src" | head -1)
    objs="$OUT/obj/${src%.c}.o"
    if [ -n "$decl" ]; then
        # shellcheck disable=SC2086 # the globs are meant to expand
        for s in $(ls $decl 2>/dev/null | grep -v '^host/cli/main\.c$' | sort -u); do
            objs="$objs $OUT/obj/${s%.*}.o"
        done
    else
        objs="$objs $OUT/libfuzzlib.a"
    fi
    {
        echo "$OUT/$name: $objs"
        printf '\t%s -fsanitize=fuzzer,address,undefined -o $@ $^ $(LDLIBS)\n' "$LINK"
        echo "all: $OUT/$name"
    } >> "$MK.tmp"
    targets="$targets $name"
done
echo '-include $(shell find '"$OUT"'/obj -name "*.d" 2>/dev/null)' >> "$MK.tmp"
mv "$MK.tmp" "$MK"
if [ -z "$targets" ]; then
    echo "build.sh: no test/fuzz/fuzz_*.c targets" >&2
    exit 0
fi
make -s --no-print-directory -f "$MK" -j"${FUZZ_JOBS:-2}" all
echo "built:$targets (in $OUT/)"
