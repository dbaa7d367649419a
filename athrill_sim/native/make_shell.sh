# The shell of the bench's evaluation of a Makefile.inc (athrill_sim/native/makefile.py): make runs every
# $(shell ...) as `/bin/sh make_shell.sh -c COMMAND`. The command runs as under /bin/sh, and a record of it
# (command, output, errors, exit status) is kept in $HAKO_SHELL_LOG, one folder per call in call order, so that
# a failing command or a listing that names no files can be reported by name.
record="$HAKO_SHELL_LOG/$(date +%s%N)-$$"
mkdir "$record" || exit 1
shift
printf '%s' "$1" > "$record/command"
/bin/sh -c "$1" > "$record/out" 2> "$record/err"
status=$?
printf '%s' "$status" > "$record/status"
cat "$record/out"
exit "$status"
