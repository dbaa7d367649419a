#!/bin/bash
# Builds the real TOPPERS Athrill emulator (athrill2, v850e2m target, VDEV/MMAP enabled).
#
# Usage: scripts/build_athrill2.sh OUT_DIR        (e.g. build/athrill; prints OUT_DIR/athrill2)
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
[ $# -eq 1 ] || die "usage: build_athrill2.sh OUT_DIR"
[ -f "$src/build_linux/Makefile" ] && [ -d "$src/athrill/src" ] \
  || die "no Athrill v850e2m sources at $src (set ATHRILL_SRC)"
src=$(cd "$src" && pwd)
out=$(mkdir -p "$1" && cd "$1" && pwd)
log=$out/build-athrill2.log
jobs=${ATHRILL_JOBS:-2}

# Stamp: every file of the source tree (path + content) and this script.
stamp=$( { (cd "$src" && find . -type f -print0 | LC_ALL=C sort -z | xargs -0 sha256sum)
           sha256sum < "${BASH_SOURCE[0]}"; } | sha256sum | cut -d' ' -f1)
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
core_mk=$tgt/athrill/build/core/linux
mkdir -p "$core_mk" "$tgt/athrill/bin/linux"

# ---------------------------------------------------------------------------------------------------------
# Core build rules. Each is run by build_linux/Makefile as `make -f $(CORE_MKDIR)/Makefile.X all` with
# build_linux as the working directory, so it includes that directory's Makefile.env (CORE_DIR, TARGET_DIR,
# WFLAGS, DFLAGS, the .c.o rule) and leaves its objects and lib*.a there. Object names must not collide
# across libraries: with -j the sub-makes run side by side in the same directory.
# ---------------------------------------------------------------------------------------------------------
supplied=()
write_mk() {  # write_mk NAME  (rules on stdin; kept if the source tree already has them)
  if [ -f "$core_mk/Makefile.$1" ]; then cat > /dev/null; else cat > "$core_mk/Makefile.$1"; supplied+=("$1"); fi
}
mk_tail='
CFLAGS	:= $(WFLAGS)
CFLAGS	+= $(IFLAGS)

all:	$(LIBTARGET)

$(LIBTARGET):	$(OBJS)
	$(AR) $(AFLAGS) $(LIBTARGET) $(OBJS)

clean:
	$(RM) -f $(OBJS) $(LIBTARGET)
'

# libmain: the emulator's entry point, option parsing and the CPU-emulation main loop.
write_mk main <<EOF
include Makefile.env

LIBTARGET	:= libmain.a

IFLAGS	:= -I\$(CORE_DIR)/inc
IFLAGS	+= -I\$(CORE_DIR)/main
IFLAGS	+= -I\$(CORE_DIR)/cpu
IFLAGS	+= -I\$(CORE_DIR)/bus
IFLAGS	+= -I\$(CORE_DIR)/lib
IFLAGS	+= -I\$(CORE_DIR)/lib/dwarf
IFLAGS	+= -I\$(CORE_DIR)/device/mpu
IFLAGS	+= -I\$(CORE_DIR)/device/peripheral/serial/fifo
IFLAGS	+= -I\$(CORE_DIR)/debugger/interaction
IFLAGS	+= -I\$(CORE_DIR)/debugger/interaction/inc
IFLAGS	+= -I\$(CORE_DIR)/debugger/executor
IFLAGS	+= -I\$(TARGET_DIR)/cpu
IFLAGS	+= -I\$(TARGET_DIR)/cpu/config
IFLAGS	+= -I\$(TARGET_DIR)/device
IFLAGS	+= -I\$(TARGET_DIR)/debugger/interaction/inc

VPATH	:=	\$(CORE_DIR)/main
VPATH	+=	\$(CORE_DIR)/main/option

OBJS	:=	main.o
OBJS	+=	cpuemu.o
OBJS	+=	option.o
$mk_tail
EOF

# libcui: the debugger (parser, executor, CPU control) and its console / UDP front ends. (lib/cui/tcp is
# stale - it no longer compiles against lib/tcp - and main.c does not use it.)
write_mk cui <<EOF
include Makefile.env

LIBTARGET	:= libcui.a

IFLAGS	:= -I\$(CORE_DIR)/inc
IFLAGS	+= -I\$(CORE_DIR)/main
IFLAGS	+= -I\$(CORE_DIR)/cpu
IFLAGS	+= -I\$(CORE_DIR)/bus
IFLAGS	+= -I\$(CORE_DIR)/lib
IFLAGS	+= -I\$(CORE_DIR)/lib/dwarf
IFLAGS	+= -I\$(CORE_DIR)/lib/dwarf/data_type
IFLAGS	+= -I\$(CORE_DIR)/device/mpu
IFLAGS	+= -I\$(CORE_DIR)/debugger/interaction
IFLAGS	+= -I\$(CORE_DIR)/debugger/interaction/inc
IFLAGS	+= -I\$(CORE_DIR)/debugger/interaction/front
IFLAGS	+= -I\$(CORE_DIR)/debugger/executor
IFLAGS	+= -I\$(CORE_DIR)/debugger/executor/concrete_executor/target
IFLAGS	+= -I\$(TARGET_DIR)/cpu
IFLAGS	+= -I\$(TARGET_DIR)/cpu/config
IFLAGS	+= -I\$(TARGET_DIR)/device
IFLAGS	+= -I\$(TARGET_DIR)/debugger/interaction/inc

VPATH	:=	\$(CORE_DIR)/debugger/executor/concrete_executor
VPATH	+=	\$(CORE_DIR)/debugger/executor/concrete_executor/util
VPATH	+=	\$(CORE_DIR)/debugger/executor/cpu_control
VPATH	+=	\$(CORE_DIR)/debugger/interaction/front/parser
VPATH	+=	\$(CORE_DIR)/debugger/interaction/front/parser/concrete_parser
VPATH	+=	\$(CORE_DIR)/lib/cui
VPATH	+=	\$(CORE_DIR)/lib/cui/stdio
VPATH	+=	\$(CORE_DIR)/lib/cui/udp

OBJS	:=	dbg_std_executor.o
OBJS	+=	dbg_print_data_type.o
OBJS	+=	dbg_cpu_callback.o
OBJS	+=	dbg_cpu_control.o
OBJS	+=	dbg_cpu_thread_control.o
OBJS	+=	dbg_parser.o
OBJS	+=	dbg_parser_config.o
OBJS	+=	dbg_std_parser.o
OBJS	+=	cui_ops.o
OBJS	+=	cui_ops_stdio.o
OBJS	+=	cui_ops_udp.o
$mk_tail
EOF

# libbus: the guest bus (address decoding to the MPU regions).
write_mk bus <<EOF
include Makefile.env

LIBTARGET	:= libbus.a

IFLAGS	:= -I\$(CORE_DIR)/inc
IFLAGS	+= -I\$(CORE_DIR)/bus
IFLAGS	+= -I\$(CORE_DIR)/cpu
IFLAGS	+= -I\$(CORE_DIR)/lib
IFLAGS	+= -I\$(CORE_DIR)/device/mpu
IFLAGS	+= -I\$(TARGET_DIR)/cpu
IFLAGS	+= -I\$(TARGET_DIR)/cpu/config

VPATH	:=	\$(CORE_DIR)/bus

OBJS	:=	bus.o
$mk_tail
EOF

# libmpu: guest memory regions (incl. the MMAP files), their allocator, the ELF image loader and the
# target's memory-map configuration.
write_mk mpu <<EOF
include Makefile.env

LIBTARGET	:= libmpu.a

IFLAGS	:= -I\$(CORE_DIR)/inc
IFLAGS	+= -I\$(CORE_DIR)/cpu
IFLAGS	+= -I\$(CORE_DIR)/lib
IFLAGS	+= -I\$(CORE_DIR)/lib/dwarf
IFLAGS	+= -I\$(CORE_DIR)/lib/dwarf/data_type
IFLAGS	+= -I\$(CORE_DIR)/device/mpu
IFLAGS	+= -I\$(CORE_DIR)/device/peripheral/serial/fifo
IFLAGS	+= -I\$(TARGET_DIR)/cpu
IFLAGS	+= -I\$(TARGET_DIR)/cpu/config

VPATH	:=	\$(CORE_DIR)/device/mpu
VPATH	+=	\$(CORE_DIR)/device/mpu/loader
VPATH	+=	\$(TARGET_DIR)/cpu/config

OBJS	:=	mpu.o
OBJS	+=	mpu_malloc.o
OBJS	+=	loader.o
OBJS	+=	mpu_config.o
$mk_tail
EOF

# libloader: ELF section / DWARF readers and the symbol tables built from them.
write_mk loader <<EOF
include Makefile.env

LIBTARGET	:= libloader.a

IFLAGS	:= -I\$(CORE_DIR)/inc
IFLAGS	+= -I\$(CORE_DIR)/cpu
IFLAGS	+= -I\$(CORE_DIR)/lib
IFLAGS	+= -I\$(CORE_DIR)/lib/dwarf
IFLAGS	+= -I\$(CORE_DIR)/lib/dwarf/data_type
IFLAGS	+= -I\$(CORE_DIR)/device/mpu
IFLAGS	+= -I\$(TARGET_DIR)/cpu
IFLAGS	+= -I\$(TARGET_DIR)/cpu/config

VPATH	:=	\$(CORE_DIR)/lib
VPATH	+=	\$(CORE_DIR)/lib/dwarf
VPATH	+=	\$(CORE_DIR)/lib/dwarf/data_type

OBJS	:=	elf_section.o
OBJS	+=	elf_dwarf_abbrev.o
OBJS	+=	elf_dwarf_info.o
OBJS	+=	elf_dwarf_info_ops.o
OBJS	+=	elf_dwarf_line.o
OBJS	+=	elf_dwarf_loc.o
OBJS	+=	elf_dwarf_util.o
OBJS	+=	elf_dwarf_data_type.o
OBJS	+=	elf_dwarf_array_type.o
OBJS	+=	elf_dwarf_base_type.o
OBJS	+=	elf_dwarf_enum_type.o
OBJS	+=	elf_dwarf_pointer_type.o
OBJS	+=	elf_dwarf_struct_type.o
OBJS	+=	elf_dwarf_subprogram_type.o
OBJS	+=	elf_dwarf_typedef_type.o
OBJS	+=	elf_dwarf_variable_type.o
OBJS	+=	file_address_mapping.o
OBJS	+=	symbol_ops.o
$mk_tail
EOF

# libstd: host-side utilities (hash, tokens, files, TCP/UDP sockets, buffers).
# (dbg_log.o is not here: the target's Makefile.cpu already builds it into libcpu.)
write_mk std <<EOF
include Makefile.env

LIBTARGET	:= libstd.a

IFLAGS	:= -I\$(CORE_DIR)/inc
IFLAGS	+= -I\$(CORE_DIR)/lib

VPATH	:=	\$(CORE_DIR)/lib
VPATH	+=	\$(CORE_DIR)/lib/tcp
VPATH	+=	\$(CORE_DIR)/lib/udp
VPATH	+=	\$(CORE_DIR)/lib/winsock_wrapper

OBJS	:=	hash.o
OBJS	+=	token.o
OBJS	+=	file.o
OBJS	+=	comm_buffer.o
OBJS	+=	tcp_socket.o
OBJS	+=	tcp_client.o
OBJS	+=	tcp_connection.o
OBJS	+=	tcp_server.o
OBJS	+=	udp_comm.o
OBJS	+=	winsock_wrapper.o
$mk_tail
EOF

# libmros: mROS (a small ROS node over host sockets) behind the CAN device.
write_mk mros <<EOF
include Makefile.env

LIBTARGET	:= libmros.a

MROS_ATHRILL	:= \$(CORE_DIR)/device/peripheral/mros-dev/mros-athrill
MROS_SRC	:= \$(CORE_DIR)/device/peripheral/mros-dev/mros-src

IFLAGS	:= -I\$(CORE_DIR)/inc
IFLAGS	+= -I\$(CORE_DIR)/cpu
IFLAGS	+= -I\$(CORE_DIR)/lib
IFLAGS	+= -I\$(CORE_DIR)/device/mpu
IFLAGS	+= -I\$(CORE_DIR)/device/peripheral/target
IFLAGS	+= -I\$(MROS_ATHRILL)/api
IFLAGS	+= -I\$(MROS_ATHRILL)/config
IFLAGS	+= -I\$(MROS_ATHRILL)/config/os/target/os_asp
IFLAGS	+= -I\$(MROS_ATHRILL)/device
IFLAGS	+= -I\$(MROS_ATHRILL)/target/os
IFLAGS	+= -I\$(MROS_ATHRILL)/target
IFLAGS	+= -I\$(MROS_SRC)/api
IFLAGS	+= -I\$(MROS_SRC)/inc
IFLAGS	+= -I\$(MROS_SRC)/comm/cimpl
IFLAGS	+= -I\$(MROS_SRC)/comm/cimpl/target/lwip
IFLAGS	+= -I\$(MROS_SRC)/node/cimpl
IFLAGS	+= -I\$(MROS_SRC)/os/target/os_asp
IFLAGS	+= -I\$(MROS_SRC)/packet/cimpl
IFLAGS	+= -I\$(MROS_SRC)/packet/cimpl/version/kinetic
IFLAGS	+= -I\$(MROS_SRC)/packet/template/version/kinetic
IFLAGS	+= -I\$(MROS_SRC)/protocol/cimpl
IFLAGS	+= -I\$(MROS_SRC)/topic/cimpl
IFLAGS	+= -I\$(MROS_SRC)/transfer/cimpl
IFLAGS	+= -I\$(TARGET_DIR)/cpu
IFLAGS	+= -I\$(TARGET_DIR)/cpu/config

VPATH	:=	\$(MROS_ATHRILL)/api
VPATH	+=	\$(MROS_ATHRILL)/config
VPATH	+=	\$(MROS_ATHRILL)/config/os/target/os_asp
VPATH	+=	\$(MROS_ATHRILL)/device
VPATH	+=	\$(MROS_ATHRILL)/target/lwip
VPATH	+=	\$(MROS_ATHRILL)/target/os
VPATH	+=	\$(MROS_SRC)/comm/cimpl
VPATH	+=	\$(MROS_SRC)/comm/cimpl/target/lwip
VPATH	+=	\$(MROS_SRC)/lib
VPATH	+=	\$(MROS_SRC)/node/cimpl
VPATH	+=	\$(MROS_SRC)/os
VPATH	+=	\$(MROS_SRC)/os/target/os_asp
VPATH	+=	\$(MROS_SRC)/packet/cimpl/version/kinetic
VPATH	+=	\$(MROS_SRC)/protocol/cimpl
VPATH	+=	\$(MROS_SRC)/topic/cimpl
VPATH	+=	\$(MROS_SRC)/transfer/cimpl

OBJS	:=	ros_cimpl.o
OBJS	+=	mros_sys_config.o
OBJS	+=	mros_usr_config.o
OBJS	+=	mros_os_config.o
OBJS	+=	athrill_mros_device.o
OBJS	+=	lwip_linux.o
OBJS	+=	mros_exclusive_ops_linux.o
OBJS	+=	os_asp.o
OBJS	+=	mros_comm_socket_cimpl.o
OBJS	+=	mros_comm_tcp_client_cimpl.o
OBJS	+=	mros_comm_tcp_client_factory_cimpl.o
OBJS	+=	mros_comm_tcp_server_cimpl.o
OBJS	+=	mros_comm_cimpl.o
OBJS	+=	mros_memory.o
OBJS	+=	mros_name.o
OBJS	+=	mros_wait_queue.o
OBJS	+=	mros_node_cimpl.o
OBJS	+=	mros_exclusive_area.o
OBJS	+=	mros_exclusive_ops.o
OBJS	+=	mros_os.o
OBJS	+=	mros_packet_decoder_cimpl.o
OBJS	+=	mros_packet_encoder_cimpl.o
OBJS	+=	mros_protocol_client_rpc_cimpl.o
OBJS	+=	mros_protocol_master_cimpl.o
OBJS	+=	mros_protocol_operation_cimpl.o
OBJS	+=	mros_protocol_publish_cimpl.o
OBJS	+=	mros_protocol_server_proc_cimpl.o
OBJS	+=	mros_protocol_slave_cimpl.o
OBJS	+=	mros_protocol_subscribe_cimpl.o
OBJS	+=	mros_topic_cimpl.o
OBJS	+=	mros_topic_connector_cimpl.o
OBJS	+=	mros_topic_connector_factory_cimpl.o
OBJS	+=	mros_topic_data_publisher_cimpl.o
OBJS	+=	mros_topic_data_subscriber_cimpl.o
$mk_tail
# host sockets instead of lwIP (mros_comm_cimpl.c)
CFLAGS	+= -DTARGET_ATHRILL
EOF

# libcpu / libdevice are target-specific: build_linux uses its own Makefile.cpu / Makefile.device. The core
# entries only forward to them so that `make -f $(CORE_MKDIR)/Makefile.{cpu,device}` works as well.
for lib in cpu device; do
  write_mk "$lib" <<EOF
# The CPU and device libraries are defined by the target (\$(TARGET_MKDIR)/Makefile.$lib).
include \$(dir \$(lastword \$(MAKEFILE_LIST)))/../../../../build_linux/Makefile.$lib
EOF
done

# ---------------------------------------------------------------------------------------------------------
t0=$(date +%s)
{
  echo "# build_athrill2.sh: sources $src"
  echo "# core build rules supplied by this script: ${supplied[*]:-none}"
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
