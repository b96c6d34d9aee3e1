#!/usr/bin/env bash
# Runs one line of an hmdlod bench plan as a Slurm array task (docs/bench.md, "Slurm").
#
#   build/hmdlod bench --plan plan.txt --out /shared/fs/bench      # on a node that sees the same paths
#   sbatch --array=1-$(wc -l < plan.txt) scripts/slurm-bench.sh plan.txt
#   build/hmdlod bench --merge /shared/fs/bench                      # when every task has finished
#
# Task N runs line N of the plan (each line is a complete `hmdlod replay ... --out DIR/runs[-R]/ID --quiet`
# command with absolute paths, shell-quoted). A task that fails leaves no summary.json in its run
# folder, so --merge names it as missing; resubmit just those with --array=N,M.
# Limit how many run at once on a node with, e.g., --array=1-140%8: timings are only comparable
# between runs that shared a machine's load the same way.
#SBATCH --job-name=hmdlod-bench
#SBATCH --cpus-per-task=2
#SBATCH --time=00:20:00
#SBATCH --output=hmdlod-bench-%A_%a.log
set -euo pipefail
plan=${1:?usage: sbatch --array=1-N scripts/slurm-bench.sh PLAN_FILE}
task=${SLURM_ARRAY_TASK_ID:?not running as a Slurm array task (submit with sbatch --array=1-N)}
line=$(sed -n "${task}p" "$plan")
[ -n "$line" ] || { echo "slurm-bench: $plan has no line $task" >&2; exit 1; }
echo "slurm-bench: task $task: $line"
exec bash -c "$line"
