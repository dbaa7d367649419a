#!/bin/bash
# Builds the v850-elf cross toolchain `hako build` compiles EV3RT programs with: binutils 2.40, gcc 12.2.0 (C and
# C++, with libstdc++) and newlib 3.3.0, for EV3RT's RH850 ABI (-mv850e2v3 -mhard-float -mdisable-callt), from
# Debian 12's source packages (binutils-source, gcc-12-source, newlib-source: their tarballs under /usr/src) or
# the upstream tarballs they hold. The gcc configuration is the one of the toolchain ../shared ships
# (`v850-elf-gcc -v`), which EV3RT's images were checked with; tests/athrill/test_v850_toolchain_script.py holds it
# there.
#
# Two things athrill2 needs are built in: target libraries with -gdwarf-2 (its DWARF reader knows 2 and 3 only)
# and a specs file that gives gas -mv850e2v3 by default and -mno-bcond17 always (athrill's v850e2m decoder
# lacks the b<cond> disp17 form binutils relaxes to).
#
# About 35 minutes on 2 cores. `hako build` then finds the compiler on PATH or with --toolchain PREFIX.
set -euo pipefail

BINUTILS_VERSION=2.40
GCC_VERSION=12.2.0
NEWLIB_VERSION=3.3.0
TARGET=v850-elf
DEBIAN_PACKAGES=(binutils-source gcc-12-source newlib-source)
BUILD_DEPS=(build-essential libgmp-dev libmpfr-dev libmpc-dev zlib1g-dev texinfo bison flex xz-utils)
TARGET_FLAGS="-gdwarf-2 -O2 -mv850e2v3 -mhard-float -mdisable-callt -Wa,-mno-bcond17"
GFDL_PATCH=gcc-gfdl-build.diff  # Debian's: the dfsg tarball lacks the GFDL manuals the build wants (s-tm-texi)

usage() {
    cat <<EOF
Usage: $0 [OPTIONS] PREFIX

Build the v850-elf cross toolchain (binutils $BINUTILS_VERSION, gcc $GCC_VERSION C/C++, newlib $NEWLIB_VERSION)
into PREFIX, for \`hako build\` (put PREFIX/bin on PATH, or pass --toolchain PREFIX).

Options:
  --sources DIR       folder holding binutils-$BINUTILS_VERSION.tar.*, gcc-$GCC_VERSION[-dfsg].tar.* and
                      newlib-$NEWLIB_VERSION.tar.* [default: Debian's /usr/src, from
                      apt-get install ${DEBIAN_PACKAGES[*]}]
  --install-deps      apt-get install the source packages and the build dependencies first
  --work DIR          build folder, kept [default: a temporary folder, removed at the end]
  --jobs N            parallel make jobs [default: the number of cores]
  --c-only            gcc for C only (no C++ or libstdc++)
  --print-configure   print the configure command lines and exit, building nothing
  -h, --help          this help
EOF
}

fail() {
    echo "Error: $*" >&2
    exit 2
}

SOURCES="" WORK="" JOBS="$(nproc 2>/dev/null || echo 2)" LANGUAGES="c,c++" PRINT_ONLY=0 INSTALL_DEPS=0 PREFIX=""
while [ $# -gt 0 ]; do
    case "$1" in
        -h|--help) usage; exit 0 ;;
        --sources) [ $# -ge 2 ] || fail "--sources needs a folder"; SOURCES="$2"; shift 2 ;;
        --work) [ $# -ge 2 ] || fail "--work needs a folder"; WORK="$2"; shift 2 ;;
        --jobs)
            [ $# -ge 2 ] && [[ "$2" =~ ^[1-9][0-9]*$ ]] || fail "--jobs needs a whole number of 1 or more"
            JOBS="$2"; shift 2 ;;
        --c-only) LANGUAGES="c"; shift ;;
        --print-configure) PRINT_ONLY=1; shift ;;
        --install-deps) INSTALL_DEPS=1; shift ;;
        -*) fail "unknown option $1 (see --help)" ;;
        *) [ -z "$PREFIX" ] || fail "one PREFIX only, got '$PREFIX' and '$1'"; PREFIX="$1"; shift ;;
    esac
done
[ -n "$PREFIX" ] || fail "give the PREFIX to install into (see --help)"
case "$PREFIX" in /*) ;; *) PREFIX="$PWD/$PREFIX" ;; esac

binutils_configure() {
    echo "$1/configure --target=$TARGET --prefix=$PREFIX --disable-nls --disable-werror --with-system-zlib"
}

gcc_configure() {
    local cxx=""
    [ "$LANGUAGES" = "c" ] || cxx=" --disable-libstdcxx-pch --disable-tls --disable-libstdcxx-verbose"
    echo "$1/configure --target=$TARGET --enable-languages=$LANGUAGES --with-newlib$cxx --disable-nls" \
         "--disable-shared --disable-threads --disable-libssp --prefix=$PREFIX --with-cpu=v850e2v3" \
         "--disable-multilib --disable-lto --disable-libquadmath --disable-libgomp --disable-werror" \
         "--with-system-zlib --with-as=$PREFIX/bin/$TARGET-as --with-ld=$PREFIX/bin/$TARGET-ld CFLAGS=-O2" \
         "CXXFLAGS=-O2 'CFLAGS_FOR_TARGET=$TARGET_FLAGS' 'CXXFLAGS_FOR_TARGET=$TARGET_FLAGS'"
}

if [ "$PRINT_ONLY" = 1 ]; then
    binutils_configure "../src/binutils-$BINUTILS_VERSION"
    gcc_configure "../src/gcc-$GCC_VERSION"
    exit 0
fi

if [ "$INSTALL_DEPS" = 1 ]; then
    apt-get install -y --no-install-recommends "${DEBIAN_PACKAGES[@]}" "${BUILD_DEPS[@]}"
fi

# The first file of the given names (any compression tar reads), in the sources folder or Debian's.
find_tarball() {
    local what="$1"; shift
    local dirs=("$SOURCES")
    [ -n "$SOURCES" ] || dirs=(/usr/src/binutils /usr/src/gcc-12 /usr/src/newlib)
    for d in "${dirs[@]}"; do
        for name in "$@"; do
            for f in "$d/$name".tar.xz "$d/$name".tar.gz "$d/$name".tar.bz2; do
                [ -f "$f" ] && { echo "$f"; return 0; }
            done
        done
    done
    fail "no $what source tarball ($*.tar.*) in ${dirs[*]}: apt-get install ${DEBIAN_PACKAGES[*]}" \
         "(or pass --sources DIR holding the upstream tarballs)"
}

BINUTILS_TAR=$(find_tarball binutils "binutils-$BINUTILS_VERSION")
GCC_TAR=$(find_tarball gcc "gcc-$GCC_VERSION-dfsg" "gcc-$GCC_VERSION")
NEWLIB_TAR=$(find_tarball newlib "newlib-$NEWLIB_VERSION")
for tool in make cc c++ tar patch bison flex makeinfo; do
    command -v "$tool" >/dev/null || fail "$tool is not installed (--install-deps installs ${BUILD_DEPS[*]})"
done

if [ -z "$WORK" ]; then
    WORK=$(mktemp -d -t v850-toolchain.XXXXXX)
    trap 'rm -rf "$WORK"' EXIT
fi
mkdir -p "$WORK/src" "$PREFIX"
WORK=$(cd "$WORK" && pwd)

unpack() {  # the tarball into $WORK/src; prints the folder it made
    local top
    top=$( (tar tf "$1" || true) | head -1 | cut -d/ -f1)  # tar is cut off by head: no pipefail here
    tar xf "$1" -C "$WORK/src"
    echo "$WORK/src/$top"
}

echo "== binutils from $BINUTILS_TAR"
BINUTILS_SRC=$(unpack "$BINUTILS_TAR")
mkdir -p "$WORK/build-binutils" && cd "$WORK/build-binutils"
eval "$(binutils_configure "$BINUTILS_SRC")"
make -j"$JOBS" MAKEINFO=true
make install MAKEINFO=true

echo "== gcc from $GCC_TAR, newlib from $NEWLIB_TAR"
GCC_SRC=$(unpack "$GCC_TAR")
NEWLIB_SRC=$(unpack "$NEWLIB_TAR")  # Debian's unpacks as newlib-salsa/
if [[ "$GCC_TAR" == *-dfsg.* ]]; then
    PATCH=$(dirname "$GCC_TAR")/debian/patches/$GFDL_PATCH
    [ -f "$PATCH" ] || PATCH=$(dirname "$GCC_TAR")/$GFDL_PATCH
    [ -f "$PATCH" ] || fail "the dfsg gcc tarball needs Debian's $GFDL_PATCH (in gcc-12-source's debian/patches)"
    (cd "$GCC_SRC" && patch -p2 < "$PATCH")
fi
ln -sfn "$NEWLIB_SRC/newlib" "$GCC_SRC/newlib"  # gcc's combined tree builds newlib as a target library
ln -sfn "$NEWLIB_SRC/libgloss" "$GCC_SRC/libgloss"
mkdir -p "$WORK/build-gcc" && cd "$WORK/build-gcc"
export PATH="$PREFIX/bin:$PATH"
eval "$(gcc_configure "$GCC_SRC")"
make -j"$JOBS" all MAKEINFO=true
make install MAKEINFO=true

echo "== specs: gas gets -mv850e2v3 by default and -mno-bcond17 always"
GCC="$PREFIX/bin/$TARGET-gcc"
SPECS="$(dirname "$("$GCC" -print-libgcc-file-name)")/specs"
"$GCC" -dumpspecs | sed 's/%{!mv850es:%{mv\*:-mv%\*}}/& %{!mv*:%(subtarget_asm_spec)} -mno-bcond17/' > "$SPECS.new"
grep -q -- '-mno-bcond17' "$SPECS.new" || fail "the specs edit did not apply (gcc's asm spec is not the one expected)"
mv "$SPECS.new" "$SPECS"

echo "== check: a C$([ "$LANGUAGES" = c ] || echo " and a C++") program for EV3RT's ABI"
cd "$WORK"
printf 'int main(void) { return 0; }\n' > check.c
# shellcheck disable=SC2086
"$GCC" $TARGET_FLAGS -c check.c -o check.o
if [ "$LANGUAGES" != c ]; then
    printf '#include <vector>\nint f() { std::vector<int> v{1, 2}; return v.size(); }\n' > check.cpp
    # shellcheck disable=SC2086
    "$PREFIX/bin/$TARGET-g++" $TARGET_FLAGS -c check.cpp -o check_cpp.o
fi
echo "built $GCC ($("$GCC" -dumpversion)): export PATH=$PREFIX/bin:\$PATH, or hako build --toolchain $PREFIX"
