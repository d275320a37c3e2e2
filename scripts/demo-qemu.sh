#!/usr/bin/env bash
# Sourced by the demo scripts: start the firmware's QEMU board binary with UART0 on a pty, and
# make sure no QEMU outlives the script.
#   qemu_start ELF LOG [extra qemu-system-arm args...]   sets qemu_pid and qemu_pty, resumes QEMU
#   qemu_stop                                            quits QEMU (also run on EXIT)
# QEMU starts halted (-S) because QEMU 7.2 drops pty output until someone has the slave open: the
# slave is held open on fd 3 (never read), then `cont` goes to the monitor, a fifo held on fd 4.

qemu_pid=""
qemu_pty=""
qemu_work=""

qemu_stop() {
    if [ -n "$qemu_pid" ] && kill -0 "$qemu_pid" 2>/dev/null; then
        echo quit >&4 2>/dev/null || true
        for _ in $(seq 20); do
            kill -0 "$qemu_pid" 2>/dev/null || break
            sleep 0.05
        done
        kill "$qemu_pid" 2>/dev/null || true
        wait "$qemu_pid" 2>/dev/null || true
    fi
    qemu_pid=""
    exec 3>&- 4>&- 2>/dev/null || true
    [ -z "$qemu_work" ] || rm -rf "$qemu_work"
    qemu_work=""
}

qemu_start() {
    local elf="$1" log="$2"
    shift 2
    qemu_work="$(mktemp -d)"
    trap qemu_stop EXIT
    trap 'qemu_stop; exit 130' INT TERM
    mkfifo "$qemu_work/monitor"
    qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -nographic -S \
        -serial pty -monitor stdio -kernel "$elf" "$@" \
        <"$qemu_work/monitor" >"$log" 2>&1 &
    qemu_pid=$!
    exec 4>"$qemu_work/monitor"
    qemu_pty=""
    for _ in $(seq 100); do
        qemu_pty="$(grep -o '/dev/pts/[0-9]*' "$log" | head -n1 || true)"
        [ -n "$qemu_pty" ] && break
        kill -0 "$qemu_pid" 2>/dev/null || break
        sleep 0.1
    done
    if [ -z "$qemu_pty" ]; then
        echo "QEMU did not start or name its pty (see $log)" >&2
        return 1
    fi
    exec 3<>"$qemu_pty"
    echo cont >&4
}
