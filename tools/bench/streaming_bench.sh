#!/usr/bin/env bash
# The baseline at scale (docs/performance.md, issue 9): streaming_bench in memory up to N, the
# CSV benchmarks in one process per file size (so that each peak RSS is that size's alone),
# then linear_ls itself on each CSV file under /usr/bin/time -v, and a summary: the baseline
# as a fraction of the memory-bandwidth reference, the CSV parser's MB/s, peak RSS against N.
#
#   tools/bench/streaming_bench.sh                  # N up to 10^8: ~6 GB of disk, ~3 GB of RAM
#   ACCELCAL_BENCH_MAX_SAMPLES=10000000 tools/bench/streaming_bench.sh
#   ACCELCAL_BUILD_DIR=/tmp/build tools/bench/streaming_bench.sh
#
# The CSV files go to a temporary folder under $TMPDIR (default /tmp), removed at exit.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=${ACCELCAL_BUILD_DIR:-$root/build}/bin
max_samples=${ACCELCAL_BENCH_MAX_SAMPLES:-100000000}
python=${PYTHON:-/usr/bin/python3}  # Debian's; the python3 first on PATH may differ

for binary in streaming_bench linear_ls; do
  [ -x "$bin/$binary" ] || { echo "no $bin/$binary: build first (or set ACCELCAL_BUILD_DIR)" >&2; exit 2; }
done
[ -x /usr/bin/time ] || { echo "/usr/bin/time is missing: apt-get install time" >&2; exit 2; }

work=$(mktemp -d "${TMPDIR:-/tmp}/streaming_bench.XXXXXX")
trap 'rm -rf "$work"' EXIT
# About 56 bytes per sample, and room to spare.
needed_kb=$((max_samples * 64 / 1024 + 1048576))
available_kb=$(df -Pk "$work" | awk 'NR == 2 { print $4 }')
if [ "$available_kb" -lt "$needed_kb" ]; then
  echo "$work has $((available_kb / 1024)) MiB free; N = $max_samples needs about" \
    "$((needed_kb / 1024)) MiB: free some or lower ACCELCAL_BENCH_MAX_SAMPLES" >&2
  exit 2
fi
export ACCELCAL_BENCH_DIR=$work ACCELCAL_BENCH_MAX_SAMPLES=$max_samples

echo "== in memory: the baseline against a plain pass over the same bytes"
"$bin/streaming_bench" --benchmark_filter='^BM_(BaselineInMemory|MemoryBandwidth)/' \
  --benchmark_out="$work/in_memory.json" --benchmark_out_format=json

csv_sizes=()
for n in 1000000 10000000 100000000; do
  [ "$n" -le "$max_samples" ] && csv_sizes+=("$n")
done
for n in "${csv_sizes[@]}"; do
  echo
  echo "== CSV, $n samples (one process)"
  "$bin/streaming_bench" --benchmark_filter="^BM_(ReadCsvFile|ParseCsv|StreamCsv)/$n/" \
    --benchmark_out="$work/csv_$n.json" --benchmark_out_format=json
done

printf 'Posici\xc3\xb3n inicial = [0 0]\nVelocidad inicial = [1 3]\nvarianza del ruido de los aceler\xc3\xb3metros = [0.25 0.64]\n' \
  >"$work/datos.txt"
for n in "${csv_sizes[@]}"; do
  echo
  echo "== linear_ls --calibration_file=<$n-sample CSV> (/usr/bin/time -v)"
  /usr/bin/time -v -o "$work/time_$n.txt" "$bin/linear_ls" \
    --calibration_file="$work/calibration_$n.csv" --conditions_file="$work/datos.txt"
  grep -E 'Elapsed \(wall clock\)|Maximum resident set size' "$work/time_$n.txt"
done
if [ "${#csv_sizes[@]}" -gt 0 ]; then
  # Without the samples kept for Ceres up to --ceres_max_samples: the stream alone.
  n=${csv_sizes[-1]}
  echo
  echo "== linear_ls --ceres_max_samples=0 --calibration_file=<$n-sample CSV> (/usr/bin/time -v)"
  /usr/bin/time -v -o "$work/time_${n}_no_ceres.txt" "$bin/linear_ls" --ceres_max_samples=0 \
    --calibration_file="$work/calibration_$n.csv" --conditions_file="$work/datos.txt" >/dev/null
  grep -E 'Elapsed \(wall clock\)|Maximum resident set size' "$work/time_${n}_no_ceres.txt"
fi

echo
echo "== summary"
"$python" - "$work" "${csv_sizes[@]}" <<'EOF'
import json, re, sys

work, sizes = sys.argv[1], sys.argv[2:]

def runs(path, arguments=1):
    # Keyed by name and arguments: "BM_ParseCsv/1000000", without "/real_time".
    return {"/".join(b["name"].split("/")[:1 + arguments]): b
            for b in json.load(open(path))["benchmarks"]}

def table(header, rows):
    widths = [max(len(str(cell)) for cell in column) for column in zip(header, *rows)]
    for cells in [header] + rows:
        print("  " + "  ".join(str(cell).rjust(width) for cell, width in zip(cells, widths)))

memory = runs(f"{work}/in_memory.json", arguments=2)
rows = []
for name, run in memory.items():
    if name.startswith("BM_BaselineInMemory/"):
        _, n, threads = name.split("/")
        reference = memory[f"BM_MemoryBandwidth/{n}/{threads}"]
        # The machine's limit: the fastest plain pass at this N, on any number of threads.
        limit = max(b["bytes_per_second"] for key, b in memory.items()
                    if key.startswith(f"BM_MemoryBandwidth/{n}/"))
        rows.append([f"{int(n):,}", threads, f"{run['bytes_per_second'] / 1e6:.0f}",
                     f"{run['items_per_second'] / 1e6:.1f} M", f"{reference['bytes_per_second'] / 1e6:.0f}",
                     f"{run['bytes_per_second'] / reference['bytes_per_second']:.3f}",
                     f"{run['bytes_per_second'] / limit:.3f}"])
print("in memory (24 bytes per sample): the baseline as a fraction of a plain pass over the same bytes,"
      " on as many threads, and of the fastest plain pass")
table(["N", "threads", "baseline MB/s", "samples/s", "plain pass MB/s", "fraction", "of fastest"], rows)

rows = []
for n in sizes:
    csv = runs(f"{work}/csv_{n}.json")
    read, parse, stream = (csv[f"{b}/{n}"] for b in ("BM_ReadCsvFile", "BM_ParseCsv", "BM_StreamCsv"))
    timing = open(f"{work}/time_{n}.txt").read()
    rss_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", timing).group(1))
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", timing).group(1)
    rows.append([f"{int(n):,}", f"{stream['file_MB']:.0f}", f"{read['bytes_per_second'] / 1e6:.0f}",
                 f"{parse['bytes_per_second'] / 1e6:.0f}", f"{stream['bytes_per_second'] / 1e6:.0f}",
                 f"{stream['items_per_second'] / 1e6:.2f} M", f"{stream['peak_rss_MiB']:.1f}",
                 f"{rss_kb / 1024:.1f}", wall])
print("\nCSV from the page cache: read(2) alone, parsing, parsing into the accumulator; peak RSS while"
      " streaming, and of linear_ls")
table(["N", "file MB", "read MB/s", "parse MB/s", "+accumulate MB/s", "samples/s",
       "peak RSS MiB", "linear_ls RSS MiB", "linear_ls wall"], rows)
EOF
