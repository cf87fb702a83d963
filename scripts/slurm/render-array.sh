#!/usr/bin/env bash
# Renders a scene as a Slurm array job: TASKS tasks, each one range of sample passes
# (`foton render --passes A..B`, a part), then a merge job that runs when all of them succeeded
# (`--dependency=afterok`) and writes OUTPUT (`foton merge`).
#
#   scripts/slurm/render-array.sh SCENE OUTPUT SPP TASKS [foton render options...]
#
# The parts go to OUTPUT.parts/ (on a file system every node sees, as the scene must be). Task i
# renders passes floor(i*SPP/TASKS) .. floor((i+1)*SPP/TASKS), so the parts tile 0..SPP. Options
# after TASKS (e.g. --resolution, --seed, --max-depth) go to every task and must be the same for
# all: merge refuses parts of other settings. Environment: FOTON (the binary; default `foton` on
# the PATH), SBATCH_OPTIONS (extra sbatch options, e.g. "--partition=render --cpus-per-task=8").
# Prints the two job ids; `foton merge --status OUTPUT.parts/*.exr` shows progress meanwhile.
set -euo pipefail

if [[ "${1:-}" == "--task" ]]; then
    # Inside the array job: this task's passes.
    shift
    scene=$1 parts=$2 spp=$3 tasks=$4
    shift 4
    i=${SLURM_ARRAY_TASK_ID:?not in a Slurm array job}
    first=$((i * spp / tasks))
    end=$(((i + 1) * spp / tasks))
    exec "${FOTON:-foton}" render "$scene" --quiet --spp "$spp" --passes "$first..$end" \
        -o "$parts/part-$i.exr" "$@"
fi

if (($# < 4)); then
    sed -n '2,15p' "$0" >&2
    exit 2
fi
scene=$(realpath "$1") output=$(realpath -m "$2") spp=$3 tasks=$4
shift 4
if ! ((spp >= 1 && tasks >= 1 && tasks <= spp)); then
    echo "error: need 1 <= TASKS <= SPP, got SPP=$spp TASKS=$tasks" >&2
    exit 2
fi
parts="$output.parts"
mkdir -p "$parts"
# SBATCH_OPTIONS is split into words on purpose.
# shellcheck disable=SC2086
array=$(sbatch --parsable ${SBATCH_OPTIONS:-} --job-name=foton-parts --array="0-$((tasks - 1))" \
    --output="$parts/task-%a.log" --export=ALL "$(realpath "$0")" --task "$scene" "$parts" \
    "$spp" "$tasks" "$@")
array=${array%%;*}
# shellcheck disable=SC2086
merge=$(sbatch --parsable ${SBATCH_OPTIONS:-} --job-name=foton-merge \
    --dependency="afterok:$array" --output="$parts/merge.log" --export=ALL \
    --wrap="$(printf '%q ' "${FOTON:-foton}" merge) $(printf '%q' "$parts")/part-*.exr -o $(printf '%q' "$output")")
merge=${merge%%;*}
echo "array job $array ($tasks tasks), merge job $merge -> $output"
