#!/bin/bash
# Builds the real TOPPERS Athrill emulator (athrill2, v850e2m target, VDEV/MMAP enabled).
#
# Usage: scripts/build_athrill2.sh [--repeatable] OUT_DIR    (e.g. build/athrill; prints OUT_DIR/athrill2)
#
# --repeatable applies scripts/athrill-patches/*.patch in order (see docs/REAL-ATHRILL.md): the VDEV MMAP sync
# wait that `--sync repeatable` needs, off unless the device config turns it on (only hakoniwa-py's repeatable
# mode does), and the fix of a store into the RX body (EV3RT's gyro reset), which kills an unpatched athrill2.
# Without the flag nothing is patched.
#
# Sources: $ATHRILL_SRC, default <repo>/../shared/third_party/athrill/src/athrill-target-v850e2m (read-only is
# fine: they are copied into a scratch dir). That copy lacks the Athrill core's build rules
# (athrill/build/core/linux/Makefile.*, dropped by a `build/` ignore rule); this script writes its own for any
# that are missing, then runs the target's build_linux/Makefile with the same options as the upstream
# build-athrill2.sh. Cached: when OUT_DIR/athrill2 exists and OUT_DIR/athrill2.stamp matches the hash of the
# source tree + this script, it prints the path and exits 0 at once. On failure it prints the tail of
# OUT_DIR/build-athrill2.log and exits non-zero. About 10 s on 2 cores here (upstream says ~1 min).
# Env: ATHRILL_SRC (sources), ATHRILL_JOBS (make -j, default 2), ATHRILL_KEEP_WORK=1 (keep the scratch dir).
set -euo pipefail

die() { echo "build_athrill2: $*" >&2; exit 1; }

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
src=${ATHRILL_SRC:-$repo/../shared/third_party/athrill/src/athrill-target-v850e2m}
patches=()
if [ "${1:-}" = "--repeatable" ]; then
  shift
  patches=("$repo"/scripts/athrill-patches/*.patch)
fi
[ $# -eq 1 ] || die "usage: build_athrill2.sh [--repeatable] OUT_DIR"
[ -f "$src/build_linux/Makefile" ] && [ -d "$src/athrill/src" ] \
  || die "no Athrill v850e2m sources at $src (set ATHRILL_SRC)"
src=$(cd "$src" && pwd)
out=$(mkdir -p "$1" && cd "$1" && pwd)
log=$out/build-athrill2.log
jobs=${ATHRILL_JOBS:-2}

# Stamp: every file of the source tree (path + content), this script and the patches applied.
stamp=$( { (cd "$src" && find . -type f -print0 | LC_ALL=C sort -z | xargs -0 sha256sum)
           sha256sum < "${BASH_SOURCE[0]}"
           for p in "${patches[@]}"; do sha256sum < "$p"; done; } | sha256sum | cut -d' ' -f1)
cached() { [ -x "$out/athrill2" ] && [ "$(cat "$out/athrill2.stamp" 2>/dev/null)" = "$stamp" ]; }
if cached; then echo "$out/athrill2"; exit 0; fi

# Several engineers share the tree: one build per OUT_DIR at a time; re-check the cache after the wait.
exec 9>"$out/.build.lock"
if command -v flock > /dev/null; then flock 9; fi
if cached; then echo "$out/athrill2"; exit 0; fi

work=$(mktemp -d "${TMPDIR:-/tmp}/athrill-build.XXXXXX")
if [ -n "${ATHRILL_KEEP_WORK:-}" ]; then echo "build_athrill2: scratch dir kept: $work" >&2
else trap 'rm -rf "$work"' EXIT; fi
cp -r "$src" "$work/athrill-target-v850e2m"
chmod -R u+w "$work"
tgt=$work/athrill-target-v850e2m
for p in "${patches[@]}"; do
  patch -s -p1 -d "$tgt" < "$p" || die "patch $p does not apply to $src"
done
core_mk=$tgt/athrill/build/core/linux
mkdir -p "$core_mk" "$tgt/athrill/bin/linux"

# ---------------------------------------------------------------------------------------------------------
# Core build rules. Each is run by build_linux/Makefile as `make -f $(CORE_MKDIR)/Makefile.X all` with
# build_linux as the working directory, so it includes that directory's Makefile.env (CORE_DIR, TARGET_DIR,
# WFLAGS, DFLAGS, the .c.o rule) and leaves its objects and lib*.a there. Object names must not collide
# across libraries: with -j the sub-makes run side by side in the same directory.
# ---------------------------------------------------------------------------------------------------------
supplied=()
# core_lib NAME INCLUDE_DIRS SOURCE_DIRS OBJECTS [PRELUDE] [POSTLUDE]: the rules of one core library, from
# three lists of words (make variables are expanded by make), plus make lines before and after them. Rules the
# source tree already has are kept.
core_lib() {
  local file="$core_mk/Makefile.$1"
  if [ -f "$file" ]; then return; fi
  supplied+=("$1")
  {
    printf 'include Makefile.env\n\nLIBTARGET\t:= lib%s.a\n%s\n' "$1" "${5:-}"
    printf 'IFLAGS\t:=\n'; printf 'IFLAGS\t+= -I%s\n' $2
    printf 'VPATH\t:=\n'; printf 'VPATH\t+= %s\n' $3
    printf 'OBJS\t:=\n'; printf 'OBJS\t+= %s\n' $4
    printf '\nCFLAGS\t:= $(WFLAGS)\nCFLAGS\t+= $(IFLAGS)\n%s\n' "${6:-}"
    printf '\nall:\t$(LIBTARGET)\n\n$(LIBTARGET):\t$(OBJS)\n\t$(AR) $(AFLAGS) $(LIBTARGET) $(OBJS)\n'
    printf '\nclean:\n\t$(RM) -f $(OBJS) $(LIBTARGET)\n'
  } > "$file"
}

# libmain: the emulator's entry point, option parsing and the CPU-emulation main loop.
core_lib main \
  '$(CORE_DIR)/inc $(CORE_DIR)/main $(CORE_DIR)/cpu $(CORE_DIR)/bus $(CORE_DIR)/lib
  $(CORE_DIR)/lib/dwarf $(CORE_DIR)/device/mpu $(CORE_DIR)/device/peripheral/serial/fifo
  $(CORE_DIR)/debugger/interaction $(CORE_DIR)/debugger/interaction/inc $(CORE_DIR)/debugger/executor
  $(TARGET_DIR)/cpu $(TARGET_DIR)/cpu/config $(TARGET_DIR)/device
  $(TARGET_DIR)/debugger/interaction/inc' \
  '$(CORE_DIR)/main $(CORE_DIR)/main/option' \
  'main.o cpuemu.o option.o'

# libcui: the debugger (parser, executor, CPU control) and its console / UDP front ends. (lib/cui/tcp is
# stale - it no longer compiles against lib/tcp - and main.c does not use it.)
core_lib cui \
  '$(CORE_DIR)/inc $(CORE_DIR)/main $(CORE_DIR)/cpu $(CORE_DIR)/bus $(CORE_DIR)/lib
  $(CORE_DIR)/lib/dwarf $(CORE_DIR)/lib/dwarf/data_type $(CORE_DIR)/device/mpu
  $(CORE_DIR)/debugger/interaction $(CORE_DIR)/debugger/interaction/inc
  $(CORE_DIR)/debugger/interaction/front $(CORE_DIR)/debugger/executor
  $(CORE_DIR)/debugger/executor/concrete_executor/target $(TARGET_DIR)/cpu $(TARGET_DIR)/cpu/config
  $(TARGET_DIR)/device $(TARGET_DIR)/debugger/interaction/inc' \
  '$(CORE_DIR)/debugger/executor/concrete_executor $(CORE_DIR)/debugger/executor/concrete_executor/util
  $(CORE_DIR)/debugger/executor/cpu_control $(CORE_DIR)/debugger/interaction/front/parser
  $(CORE_DIR)/debugger/interaction/front/parser/concrete_parser $(CORE_DIR)/lib/cui
  $(CORE_DIR)/lib/cui/stdio $(CORE_DIR)/lib/cui/udp' \
  'dbg_std_executor.o dbg_print_data_type.o dbg_cpu_callback.o dbg_cpu_control.o
  dbg_cpu_thread_control.o dbg_parser.o dbg_parser_config.o dbg_std_parser.o cui_ops.o cui_ops_stdio.o
  cui_ops_udp.o'

# libbus: the guest bus (address decoding to the MPU regions).
core_lib bus \
  '$(CORE_DIR)/inc $(CORE_DIR)/bus $(CORE_DIR)/cpu $(CORE_DIR)/lib $(CORE_DIR)/device/mpu
  $(TARGET_DIR)/cpu $(TARGET_DIR)/cpu/config' \
  '$(CORE_DIR)/bus' \
  'bus.o'

# libmpu: guest memory regions (incl. the MMAP files), their allocator, the ELF image loader and the
# target's memory-map configuration.
core_lib mpu \
  '$(CORE_DIR)/inc $(CORE_DIR)/cpu $(CORE_DIR)/lib $(CORE_DIR)/lib/dwarf
  $(CORE_DIR)/lib/dwarf/data_type $(CORE_DIR)/device/mpu $(CORE_DIR)/device/peripheral/serial/fifo
  $(TARGET_DIR)/cpu $(TARGET_DIR)/cpu/config' \
  '$(CORE_DIR)/device/mpu $(CORE_DIR)/device/mpu/loader $(TARGET_DIR)/cpu/config' \
  'mpu.o mpu_malloc.o loader.o mpu_config.o'

# libloader: ELF section / DWARF readers and the symbol tables built from them.
core_lib loader \
  '$(CORE_DIR)/inc $(CORE_DIR)/cpu $(CORE_DIR)/lib $(CORE_DIR)/lib/dwarf
  $(CORE_DIR)/lib/dwarf/data_type $(CORE_DIR)/device/mpu $(TARGET_DIR)/cpu $(TARGET_DIR)/cpu/config' \
  '$(CORE_DIR)/lib $(CORE_DIR)/lib/dwarf $(CORE_DIR)/lib/dwarf/data_type' \
  'elf_section.o elf_dwarf_abbrev.o elf_dwarf_info.o elf_dwarf_info_ops.o elf_dwarf_line.o
  elf_dwarf_loc.o elf_dwarf_util.o elf_dwarf_data_type.o elf_dwarf_array_type.o elf_dwarf_base_type.o
  elf_dwarf_enum_type.o elf_dwarf_pointer_type.o elf_dwarf_struct_type.o elf_dwarf_subprogram_type.o
  elf_dwarf_typedef_type.o elf_dwarf_variable_type.o file_address_mapping.o symbol_ops.o'

# libstd: host-side utilities (hash, tokens, files, TCP/UDP sockets, buffers).
# (dbg_log.o is not here: the target's Makefile.cpu already builds it into libcpu.)
core_lib std \
  '$(CORE_DIR)/inc $(CORE_DIR)/lib' \
  '$(CORE_DIR)/lib $(CORE_DIR)/lib/tcp $(CORE_DIR)/lib/udp $(CORE_DIR)/lib/winsock_wrapper' \
  'hash.o token.o file.o comm_buffer.o tcp_socket.o tcp_client.o tcp_connection.o tcp_server.o
  udp_comm.o winsock_wrapper.o'

# libmros: mROS (a small ROS node over host sockets) behind the CAN device.
core_lib mros \
  '$(CORE_DIR)/inc $(CORE_DIR)/cpu $(CORE_DIR)/lib $(CORE_DIR)/device/mpu
  $(CORE_DIR)/device/peripheral/target $(MROS_ATHRILL)/api $(MROS_ATHRILL)/config
  $(MROS_ATHRILL)/config/os/target/os_asp $(MROS_ATHRILL)/device $(MROS_ATHRILL)/target/os
  $(MROS_ATHRILL)/target $(MROS_SRC)/api $(MROS_SRC)/inc $(MROS_SRC)/comm/cimpl
  $(MROS_SRC)/comm/cimpl/target/lwip $(MROS_SRC)/node/cimpl $(MROS_SRC)/os/target/os_asp
  $(MROS_SRC)/packet/cimpl $(MROS_SRC)/packet/cimpl/version/kinetic
  $(MROS_SRC)/packet/template/version/kinetic $(MROS_SRC)/protocol/cimpl $(MROS_SRC)/topic/cimpl
  $(MROS_SRC)/transfer/cimpl $(TARGET_DIR)/cpu $(TARGET_DIR)/cpu/config' \
  '$(MROS_ATHRILL)/api $(MROS_ATHRILL)/config $(MROS_ATHRILL)/config/os/target/os_asp
  $(MROS_ATHRILL)/device $(MROS_ATHRILL)/target/lwip $(MROS_ATHRILL)/target/os $(MROS_SRC)/comm/cimpl
  $(MROS_SRC)/comm/cimpl/target/lwip $(MROS_SRC)/lib $(MROS_SRC)/node/cimpl $(MROS_SRC)/os
  $(MROS_SRC)/os/target/os_asp $(MROS_SRC)/packet/cimpl/version/kinetic $(MROS_SRC)/protocol/cimpl
  $(MROS_SRC)/topic/cimpl $(MROS_SRC)/transfer/cimpl' \
  'ros_cimpl.o mros_sys_config.o mros_usr_config.o mros_os_config.o athrill_mros_device.o lwip_linux.o
  mros_exclusive_ops_linux.o os_asp.o mros_comm_socket_cimpl.o mros_comm_tcp_client_cimpl.o
  mros_comm_tcp_client_factory_cimpl.o mros_comm_tcp_server_cimpl.o mros_comm_cimpl.o mros_memory.o
  mros_name.o mros_wait_queue.o mros_node_cimpl.o mros_exclusive_area.o mros_exclusive_ops.o mros_os.o
  mros_packet_decoder_cimpl.o mros_packet_encoder_cimpl.o mros_protocol_client_rpc_cimpl.o
  mros_protocol_master_cimpl.o mros_protocol_operation_cimpl.o mros_protocol_publish_cimpl.o
  mros_protocol_server_proc_cimpl.o mros_protocol_slave_cimpl.o mros_protocol_subscribe_cimpl.o
  mros_topic_cimpl.o mros_topic_connector_cimpl.o mros_topic_connector_factory_cimpl.o
  mros_topic_data_publisher_cimpl.o mros_topic_data_subscriber_cimpl.o' \
  'MROS_ATHRILL	:= $(CORE_DIR)/device/peripheral/mros-dev/mros-athrill
MROS_SRC	:= $(CORE_DIR)/device/peripheral/mros-dev/mros-src' \
  '# host sockets instead of lwIP (mros_comm_cimpl.c)
CFLAGS	+= -DTARGET_ATHRILL'

# libcpu / libdevice are target-specific: build_linux uses its own Makefile.cpu / Makefile.device. The core
# entries only forward to them so that `make -f $(CORE_MKDIR)/Makefile.{cpu,device}` works as well.
for lib in cpu device; do
  [ -f "$core_mk/Makefile.$lib" ] && continue
  supplied+=("$lib")
  cat > "$core_mk/Makefile.$lib" <<EOF
# The CPU and device libraries are defined by the target (\$(TARGET_MKDIR)/Makefile.$lib).
include \$(dir \$(lastword \$(MAKEFILE_LIST)))/../../../../build_linux/Makefile.$lib
EOF
done

# ---------------------------------------------------------------------------------------------------------
t0=$(date +%s)
{
  echo "# build_athrill2.sh: sources $src"
  echo "# core build rules supplied by this script: ${supplied[*]:-none}"
  echo "# patches applied: ${patches[*]:-none}"
} > "$log"
cd "$tgt/build_linux"
if ! make -j"$jobs" timer32=true serial_fifo_enable=true skip_clock_bugfix=true supress_detect_error=true \
        etrobo_optimize=true reuse_port=true >> "$log" 2>&1 || [ ! -x athrill2 ]; then
  # With -j the failing job's messages may sit above the other job's output: show the errors first.
  if grep -q -E 'error|Error|undefined reference' "$log"; then
    echo "build_athrill2: build failed (log: $log); errors:" >&2
    grep -E -B2 -A2 'error|undefined reference' "$log" | grep -v '^gcc ' | head -30 >&2
  fi
  echo "build_athrill2: build failed (log: $log); last lines:" >&2
  tail -15 "$log" >&2
  exit 1
fi
echo "# built in $(( $(date +%s) - t0 )) s" >> "$log"
cp athrill2 "$out/athrill2.tmp.$$"
mv -f "$out/athrill2.tmp.$$" "$out/athrill2"
echo "$stamp" > "$out/athrill2.stamp"
echo "$out/athrill2"
