#!/usr/bin/env bash
# The sensor chain end to end, one run (called by ./demo.sh; needs scripts/setup.sh first):
#   1. emulated sensor: `tactile simulate` models a compression test of the fingertip with two
#      concealed effects (gel relaxation, AC-coupled offset cut) and writes the volts at the ADC
#      inputs (out/adc-stimulus.bin), the test machine's rod/load export (out/machine.csv) and its
#      own recording (out/compression-sim.csv, the model's truth to compare with);
#   2. firmware: the QEMU board binary (mps2-an386) converts those volts with the emulated
#      ADS131M04 (file read through ARM semihosting) and runs its real driver, auto-null, framing;
#   3. serial -> host: `tactile log` records UART0's pty and merges the machine export into
#      out/compression.csv (recording-v1); stopped when the test is over. The board starts the
#      test when the host starts the stream, so the machine's time zero is the first sample
#      (`--align start`); cross-correlation would be biased by the AC coupling's phase lead;
#   4. diagnosis: `tactile diagnose` -> out/diagnosis.json and out/report.html.
# QEMU runs on a virtual clock (-icount shift=0,sleep=off: device time = executed instructions,
# idle time skipped), so the test's minutes of device time take seconds; TACTILE_DEMO_CLOCK=realtime
# paces it by SysTick against the host clock instead (as slow as the test itself, or slower).
# Usage: scripts/demo-chain.sh     Leaves out/ as above plus compression-qemu.log and plots.
#   TACTILE_DEMO_OUT=DIR   write to DIR instead of out/ (the end-to-end test does)
#   TACTILE_DEMO_PROFILE=debug   use the dev build of tactile (test.sh: `cargo test` built it, and
#                          the dev profile optimises the diagnosis) instead of a release build
#   TACTILE_DEMO_CHECK=1   fail unless the diagnosis names exactly the concealed effects, each
#                          parameter within 20 %, held-out RMSE at most half the baseline's
set -euo pipefail
cd "$(dirname "$0")/.."
out="${TACTILE_DEMO_OUT:-out}"
mkdir -p "$out"
say() { printf '\033[1m[chain]\033[0m %s\n' "$*"; }
fail() { printf '\033[1;31m[chain] FAILED:\033[0m %s\n' "$*" >&2; exit 1; }

# The concealed effects and their parameters (the diagnosis must find these, blind).
relax_tau_s=4 relax_fraction=0.3 highpass_tau_s=25
# 500 Hz: the effects are seconds slow; half the default rate halves the stream and the fit.
rate_hz=500
# Samples per frame (protocol MAX_BATCH): the device never completes the last, partial frame.
batch=16

say "build the QEMU firmware and the tactile CLI"
(cd firmware && cargo build -q --release --bin qemu-mps2-an386) || fail "firmware build"
if [ "${TACTILE_DEMO_PROFILE:-release}" = debug ]; then
    cargo build -q -p tactile --bin tactile || fail "tactile build"
    tactile=target/debug/tactile
else
    cargo build -q --release -p tactile --bin tactile || fail "tactile build"
    tactile=target/release/tactile
fi
elf=firmware/target/thumbv7em-none-eabihf/release/qemu-mps2-an386

say "1/4 emulated sensor: 2 x 60 N compression at 20 deg, ${rate_hz} Hz; concealed: relaxation (tau ${relax_tau_s} s, ${relax_fraction}) + AC coupling (tau ${highpass_tau_s} s)"
"$tactile" simulate --contact-angle 20 --azimuth 60 --peak-load 60 --then-peak-load 60 \
    --rate "$rate_hz" --noise-v 0.002 --noise-load-n 0.02 --seed 7 \
    --effect "viscoelastic_relaxation:tau_s=${relax_tau_s},fraction=${relax_fraction}" \
    --effect "highpass_coupling:tau_s=${highpass_tau_s}" \
    --out "$out/compression-sim.csv" --adc-stimulus "$out/adc-stimulus.bin" \
    --machine-csv "$out/machine.csv" || fail "tactile simulate"
records=$(($(grep -cv '^#' "$out/compression-sim.csv") - 1))
test_s=$(python3 -c "print(f'{($records - 1) / $rate_hz:.1f}')")
say "    ${records} samples (${test_s} s of test) -> $out/adc-stimulus.bin, $out/machine.csv"

# shellcheck source=scripts/demo-qemu.sh
. scripts/demo-qemu.sh
clock=()
[ "${TACTILE_DEMO_CLOCK:-virtual}" = realtime ] || clock=(-icount shift=0,sleep=off)
say "2/4 firmware under QEMU reads the stimulus through semihosting (${TACTILE_DEMO_CLOCK:-virtual} clock)"
qemu_start "$elf" "$out/compression-qemu.log" "${clock[@]}" \
    -semihosting-config "enable=on,target=native,arg=qemu-mps2-an386,arg=$out/adc-stimulus.bin" ||
    fail "QEMU did not start ($out/compression-qemu.log)"

say "3/4 tactile log records ${qemu_pty} and merges the machine's rod/load ($out/compression.csv)"
rm -f "$out/compression.csv"
started=$SECONDS
# On the virtual clock the device's stamps are the test's time (the host sees minutes pass in
# seconds), so the rows are timed by them.
device_clock=()
[ "${TACTILE_DEMO_CLOCK:-virtual}" = realtime ] || device_clock=(--device-clock)
"$tactile" log --port "$qemu_pty" --no-mcap -q -o "$out/compression.csv" "${device_clock[@]}" \
    --contact-angle-deg 20 --azimuth-deg 60 \
    --reference "$out/machine.csv" --align start &
log_pid=$!
# The board's sample clock stops after the last record: stop the logger once the recording spans
# the test in device time (all but the last, partial frame); give up if the logger ends on its
# own or nothing new arrives for 30 s.
if ! python3 - "$out/compression.csv" "$((records - batch))" "$rate_hz" "$log_pid" <<'PY'; then
import os, signal, sys, time
path, samples, rate, pid = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
need = (samples - 1) / rate
last_change, last_rows, span = time.time(), 0, 0.0
while True:
    time.sleep(0.2)
    try:  # the logger's state; Z = exited, waiting for the shell to reap it
        state = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()[0]
    except FileNotFoundError:
        state = "Z"
    if state == "Z":
        sys.exit("tactile log ended on its own")
    try:
        lines = [l for l in open(path) if not l.startswith("#") and l.strip()]
    except FileNotFoundError:
        lines = []
    if len(lines) > 2:
        col = lines[0].split(",").index("t_device_s")
        span = float(lines[-1].split(",")[col]) - float(lines[1].split(",")[col])
    if span >= need:
        os.kill(pid, signal.SIGINT)
        sys.exit(0)
    if len(lines) != last_rows:
        last_rows, last_change = len(lines), time.time()
    elif time.time() - last_change > 30:
        print(f"recording stalled at {span:.1f} of {need:.1f} s of device time", file=sys.stderr)
        sys.exit(1)
PY
    kill -INT "$log_pid" 2>/dev/null || true
    wait "$log_pid" || true
    fail "the stream stopped before the end of the test ($out/compression-qemu.log)"
fi
wait "$log_pid" || fail "tactile log"
qemu_stop
say "    recorded ${test_s} s of test in $((SECONDS - started)) s wall"
"$tactile" plot "$out/compression.csv" -o "$out/compression" >/dev/null || fail "tactile plot"

say "4/4 tactile diagnose (blind) -> $out/diagnosis.json, $out/report.html"
"$tactile" diagnose "$out/compression.csv" --json "$out/diagnosis.json" --report "$out/report.html" ||
    fail "tactile diagnose"
python3 - "$out" "$relax_tau_s" "$relax_fraction" "$highpass_tau_s" "${TACTILE_DEMO_CHECK:-0}" <<'PY' ||
import csv, json, sys
out = sys.argv[1]
tau_r, frac, tau_h = map(float, sys.argv[2:5])
check = sys.argv[5] == "1"
concealed = {"viscoelastic_relaxation": {"tau_s": tau_r, "fraction": frac},
             "highpass_coupling": {"tau_s": tau_h}}

def read(path):
    return list(csv.DictReader(l for l in open(path) if not l.startswith("#")))

# The firmware path against the sensor model, sample by sample: what the ADC, the null and the
# framing did to the volts (a constant left by the null, then quantisation).
sim, rec = read(f"{out}/compression-sim.csv"), read(f"{out}/compression.csv")
gaps = sum(1 for r in rec if r["gap"] not in ("0", ""))
print(f"recording: {len(rec)} of {len(sim)} samples, {gaps} gap rows")
for ch in ("fz_V", "mx_V", "my_V"):
    d = [float(r[ch]) - float(s[ch]) for r, s in zip(rec, sim)]
    mean = sum(d) / len(d)
    dev = max(abs(x - mean) for x in d)
    print(f"  {ch}: firmware path - model = {mean * 1e3:+.3f} mV (null residual) "
          f"+- {dev * 1e6:.2f} uV")
d = json.load(open(f"{out}/diagnosis.json"))
print(f"verdict: {d['verdict']}")
problems = []
for e in d["effects"]:
    params = ", ".join(f"{k} = {v:.3g}" for k, v in e["params"].items())
    truth = concealed.get(e["name"])
    if truth is None:
        problems.append(f"{e['name']} was not concealed")
        print(f"  effect {e['name']}: {params}  (not concealed)")
    else:
        errs = {k: e["params"][k] / v - 1 for k, v in truth.items()}
        print(f"  effect {e['name']}: {params}  (concealed: "
              + ", ".join(f"{k} = {v:g}, error {errs[k]:+.1%}" for k, v in truth.items()) + ")")
        problems += [f"{e['name']}.{k} off by {x:+.0%}" for k, x in errs.items() if abs(x) > 0.2]
    print(f"    {e['evidence']}")
missed = set(concealed) - {e["name"] for e in d["effects"]}
problems += [f"{m} missed" for m in sorted(missed)]
h = d["fit"]["heldout"]
ratio = h["rmse_after"] / h["rmse_before"]
print(f"held-out RMSE {h['rmse_before']:.4f} -> {h['rmse_after']:.4f} (x{ratio:.3f}; "
      f"{h['t_start_s']:.0f}-{h['t_end_s']:.0f} s, not fitted)")
if ratio > 0.5:
    problems.append(f"held-out RMSE only x{ratio:.2f}")
if problems:
    print("differs from the concealed truth: " + "; ".join(problems))
    sys.exit(1 if check else 0)
PY
    fail "the diagnosis did not recover the concealed effects"
