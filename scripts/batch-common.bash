# Shared by scripts/skeletonize-parallel and scripts/skeletonize-slurm (sourced, not run). They
# only hand the inputs out. vmas does the rest, in one place (docs/cli.md): it reads the input
# lists, names the outputs, keeps DIR/summary.jsonl (--summary: one JSON line per input, merged
# under a lock, so that runs at once lose nothing), says which inputs are still to run
# (--pending, by the rule of --resume) and records a run that left no line (--record).

# The vmas binary: $1 (--vmas) if given, else $VMAS, else vmas on PATH, else the build/vmas of
# the checkout whose scripts folder is $2.
find_vmas() {
  if [ -n "$1" ]; then printf '%s' "$1"
  elif [ -n "${VMAS:-}" ]; then printf '%s' "$VMAS"
  elif command -v vmas >/dev/null; then command -v vmas
  else printf '%s' "$(cd "$2/.." && pwd)/build/vmas"; fi
}

# Ends the script (die_usage, the script's own) for a VMAS_OPTION (an argument) that the
# launchers set themselves.
refuse_launcher_options() {
  local o
  for o in "$@"; do
    case "$o" in
      -o|--output|--output=*|--output-dir|--output-dir=*|--inputs|--inputs=*)
        die_usage "$o is set by this script (give --output-dir and --inputs before --)" ;;
      --summary|--summary=*|--resume|--pending|--pending=*|--record|--record=*)
        die_usage "$o is set by this script (--force runs the inputs that are up to date too)" ;;
      --labels|--labels=*) die_usage "--labels takes one input (vmas skeletonize INPUT --labels FILE)" ;;
    esac
  done
}

# Whether the VMAS_OPTIONS (the arguments) name --threads.
names_threads() {
  local o
  for o in "$@"; do
    case "$o" in --threads|--threads=*) return 0 ;; esac
  done
  return 1
}

# vmas_pending VMAS LIST ARGS...: `VMAS skeletonize ARGS --pending LIST`: the inputs a run of
# ARGS would run into LIST, and why each (on standard output). vmas checks ARGS as for a run
# first: what it refuses ends the script, with exit 2 for a usage error.
vmas_pending() {
  local vmas=$1 list=$2 status
  shift 2
  "$vmas" skeletonize "$@" --pending "$list"
  status=$?
  [ "$status" -eq 0 ] || exit $(( status == 2 ? 2 : 1 ))
}
