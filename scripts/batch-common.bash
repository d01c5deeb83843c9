# Shared by scripts/skeletonize-parallel and scripts/skeletonize-slurm (sourced, not run): the
# input list, output names, JSON lines and DIR/summary.jsonl, which a re-run merges into and
# uses to skip the inputs that are already done.

# JSON string contents for s: backslash, quote and control characters escaped.
json_escape() {
  local s=$1
  s=${s//\\/\\\\}
  s=${s//\"/\\\"}
  s=${s//$'\t'/\\t}
  s=${s//$'\r'/\\r}
  s=${s//$'\n'/\\n}
  printf '%s' "${s//[$'\001'-$'\037']/ }"
}

# A JSON array of strings: json_array a b -> ["a","b"].
json_array() {
  local out="" s
  for s in "$@"; do out+=",\"$(json_escape "$s")\""; done
  printf '[%s]' "${out#,}"
}

# Appends the paths of each LIST (one per line; blank lines and lines starting with # skipped,
# trailing blanks and CR removed) to the array `inputs`. Returns 1, the reason in list_error,
# for a list it cannot read.
read_input_lists() {
  local list line
  for list in "$@"; do
    [ -r "$list" ] || { list_error="--inputs $list: cannot read it"; return 1; }
    while IFS= read -r line || [ -n "$line" ]; do
      line=${line%$'\r'}
      while [ "${line% }" != "$line" ]; do line=${line% }; done
      [ -z "$line" ] || [ "${line:0:1}" = "#" ] || inputs+=("$line")
    done < "$list"
  done
}

# Where vmas writes the output of INPUT in DIR with FORMAT (std::filesystem::path::stem, as
# vmas names it).
output_of() {
  local name=${1##*/} dir=$2
  [ "${name%.*}" = "" ] || name=${name%.*}
  [ "$dir" = / ] && dir=""
  printf '%s/%s.%s' "$dir" "$name" "$3"
}

# The message of a JSON line's "error" (still escaped), or nothing.
error_of() {
  local error_re='"error":"(([^"\\]|\\.)*)"'
  [[ "$1" =~ $error_re ]] && printf '%s' "${BASH_REMATCH[1]}"
}

# LINE with the fields FIELDS (',"key":value...') added before its closing brace.
with_fields() { printf '%s' "${1%\}}$2}"; }

# --- DIR/summary.jsonl -------------------------------------------------------------------------
# One line per input ever run into DIR, keyed by its "input" (as the JSON line spells it). Each
# line records the vmas options of its run ("batch_options"); a re-run skips an input whose line
# has no error, the same options and an output newer than the input, and replaces the lines of
# the inputs it runs, keeping every other.
declare -A summary_line=()
summary_order=()

# Reads SUMMARY (if it exists) into summary_line and summary_order.
load_summary() {
  local line key input_re='^\{"vmas":"[^"]*","input":"(([^"\\]|\\.)*)"|^\{"input":"(([^"\\]|\\.)*)"'
  summary_line=() summary_order=()
  [ -r "$1" ] || return 0
  while IFS= read -r line || [ -n "$line" ]; do
    [[ "$line" =~ $input_re ]] || continue
    key=${BASH_REMATCH[1]:-${BASH_REMATCH[3]}}
    [ -n "${summary_line[$key]+set}" ] || summary_order+=("$key")
    summary_line[$key]=$line
  done < "$1"
}

# Whether INPUT is done: its summary line has no error and OPTIONS_FIELD (the
# ',"batch_options":[...]' of this run), and OUTPUT is not empty and newer than INPUT.
up_to_date() {
  local input=$1 output=$2 options_field=$3
  local line=${summary_line[$(json_escape "$input")]:-}
  [ -n "$line" ] && [[ "$line" != *'"error":'* ]] && [[ "$line" == *"$options_field"* ]] &&
    [ -s "$output" ] && [ "$output" -nt "$input" ]
}

# Writes SUMMARY from summary_line/summary_order with the lines NEW_LINES (an associative
# array's name, keyed by escaped input) in place of the old ones; new inputs go last, in the
# order of the array named by NEW_ORDER. Atomic (a temporary, then a rename).
merge_summary() {
  local summary=$1 key
  local -n merged_lines=$2 merged_order=$3
  {
    for key in ${summary_order[@]+"${summary_order[@]}"}; do
      printf '%s\n' "${merged_lines[$key]:-${summary_line[$key]}}"
    done
    for key in ${merged_order[@]+"${merged_order[@]}"}; do
      [ -n "${summary_line[$key]+set}" ] || printf '%s\n' "${merged_lines[$key]}"
    done
  } > "$summary.tmp" && mv "$summary.tmp" "$summary"
}

# Reads the vmas options of a batch: sets format (the outputs' extension), user_threads (1 if
# they name --threads) and user_options (them without --json). Returns 1, the reason in
# list_error, for an option the scripts set themselves or a format vmas does not write.
read_vmas_options() {
  local i o
  format=ply user_threads=0 user_options=()
  for ((i = 1; i <= $#; i++)); do
    o=${!i}
    case "$o" in
      -o|--output|--output=*|--output-dir|--output-dir=*|--inputs|--inputs=*|--labels|--labels=*)
        list_error="$o is set by this script (give --output-dir before --)"; return 1 ;;
      --format) local next=$((i + 1)); format=${!next:-} ;;
      --format=*) format=${o#*=} ;;
      --threads|--threads=*) user_threads=1 ;;
    esac
    [ "$o" = --json ] || user_options+=("$o")
  done
  [ "$format" = ply ] || [ "$format" = ma ] || { list_error="--format must be ply or ma (got '$format')"; return 1; }
}
