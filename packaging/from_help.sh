#!/usr/bin/env bash
# packaging/from_help.sh GONIO OUT_DIR [HELP2MAN]
#
# What is installed beside gonio and written from its own help texts, so that
# neither can drift from the option parsers (tools/cli/cli.h, ArgParser::help):
#   OUT_DIR/completion/gonio      bash completion: the subcommands of
#                                 `gonio --help`, each one's options from
#                                 `gonio COMMAND --help`, and what each
#                                 option's value is (a word of a choice, a
#                                 directory, a file, or free text)
#   OUT_DIR/man1/gonio.1.gz,      manual pages (help2man), one for gonio and
#   OUT_DIR/man1/gonio-COMMAND.1.gz  one per subcommand
# Run at build time by packaging/CMakeLists.txt (target gonio_manual). Without
# HELP2MAN (empty) man1/ is left empty and the completion is still written.
set -euo pipefail

gonio=$1
out=$2
help2man=${3:-}

# The subcommands and their one-line summaries: the lines of `gonio --help`
# between "Commands:" and the next blank line ("  NAME   SUMMARY").
commands=()
summaries=()
in_commands=0
while IFS= read -r line; do
  if [[ $line == "Commands:" ]]; then in_commands=1; continue; fi
  if ((in_commands)); then
    [[ -z $line ]] && break
    if [[ $line =~ ^\ \ ([a-z][a-z0-9-]*)\ +(.+)$ ]]; then
      commands+=("${BASH_REMATCH[1]}")
      summaries+=("${BASH_REMATCH[2]}")
    fi
  fi
done < <("$gonio" --help)
if ((${#commands[@]} == 0)); then
  echo "from_help.sh: '$gonio --help' lists no commands" >&2
  exit 1
fi
version=$("$gonio" --version)
version=${version##* }

# A command's options as "NAME<TAB>METAVAR" lines: the lines "  --NAME" or
# "  --NAME METAVAR" of its --help (ArgParser::help's layout).
options_of() {
  local line
  while IFS= read -r line; do
    if [[ $line =~ ^\ \ --([a-z0-9][a-z0-9-]*)(\ (.+))?$ ]]; then
      printf '%s\t%s\n' "${BASH_REMATCH[1]}" "${BASH_REMATCH[3]}"
    fi
  done < <("$gonio" "$1" --help)
}

# What an option's value is, from its metavar: "" (a flag, no value),
# "words:a b" (a choice: every alternative a lower-case word, as
# ArgParser::choice writes them), "dir", "file", or "text".
value_kind() {
  local metavar=$1
  if [[ -z $metavar ]]; then
    echo ""
  elif [[ $metavar =~ ^[a-z0-9][a-z0-9-]*(\|[a-z0-9][a-z0-9-]*)+$ ]]; then
    echo "words:${metavar//|/ }"
  elif [[ $metavar == DIR || $metavar == *_DIR ]]; then
    echo dir
  elif [[ $metavar =~ ^(FILE|MODEL|PATH)$ || $metavar =~ \.[a-z]{2,5}(\||$) ]]; then
    echo file
  else
    echo text
  fi
}

# --- bash completion -------------------------------------------------------
mkdir -p "$out/completion" "$out/man1"
completion="$out/completion/gonio"
{
  cat <<EOF
# bash completion for gonio $version. Generated at build time from
# \`gonio --help\` and every \`gonio COMMAND --help\` by packaging/from_help.sh:
# change the commands' option parsers, never this file.

_gonio_commands='${commands[*]}'

# A command's options.
_gonio_options() {
  case \$1 in
EOF
  for c in "${commands[@]}"; do
    names=$(options_of "$c" | cut -f1 | sed 's/^/--/' | tr '\n' ' ')
    printf "    %s) echo '%s' ;;\n" "$c" "$names"
  done
  cat <<'EOF'
  esac
}

# What the value of COMMAND's OPTION is: words:A B (one of them), dir, file,
# text (anything: nothing to offer), or nothing (a flag, or not an option).
_gonio_value() {
  case "$1 $2" in
EOF
  for c in "${commands[@]}"; do
    while IFS=$'\t' read -r name metavar; do
      kind=$(value_kind "$metavar")
      [[ -n $kind ]] && printf "    '%s --%s') echo '%s' ;;\n" "$c" "$name" "$kind"
    done < <(options_of "$c")
  done
  cat <<'EOF'
  esac
}

_gonio() {
  local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]} command=${COMP_WORDS[1]-}
  COMPREPLY=()
  if ((COMP_CWORD == 1)); then
    mapfile -t COMPREPLY < <(compgen -W "$_gonio_commands --help --version" -- "$cur")
    return 0
  fi
  # The option whose value is being typed: "--out DIR", or "--out=DIR"
  # (COMP_WORDBREAKS holds '=', so bash makes '=' a word of its own).
  local option=""
  if [[ $cur == "=" ]]; then
    option=$prev
    cur=""
  elif [[ $prev == "=" && $COMP_CWORD -ge 3 ]]; then
    option=${COMP_WORDS[COMP_CWORD-2]}
  elif [[ $prev == --?* ]]; then
    option=$prev
  fi
  if [[ -n $option ]]; then
    local kind
    kind=$(_gonio_value "$command" "$option")
    case $kind in
      words:*)
        mapfile -t COMPREPLY < <(compgen -W "${kind#words:}" -- "$cur")
        return 0 ;;
      dir)
        compopt -o filenames 2>/dev/null
        mapfile -t COMPREPLY < <(compgen -d -- "$cur")
        return 0 ;;
      file)
        compopt -o filenames 2>/dev/null
        mapfile -t COMPREPLY < <(compgen -f -- "$cur")
        return 0 ;;
      text) return 0 ;;
    esac
  fi
  if [[ $cur == -* ]]; then
    mapfile -t COMPREPLY < <(compgen -W "$(_gonio_options "$command")" -- "$cur")
    return 0
  fi
  # Arguments are files (photometric files, models).
  compopt -o filenames 2>/dev/null
  mapfile -t COMPREPLY < <(compgen -f -- "$cur")
  return 0
}
complete -F _gonio gonio
EOF
} > "$completion.tmp"
mv "$completion.tmp" "$completion"

# --- manual pages ----------------------------------------------------------
rm -f "$out"/man1/*.1 "$out"/man1/*.1.gz
if [[ -z $help2man ]]; then
  echo "from_help.sh: no help2man, no manual pages (scripts/setup.sh installs it)" >&2
  exit 0
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# help2man runs PROGRAM --help and names the page after PROGRAM, so each page
# has a wrapper named after it. ArgParser::help puts an option's text on the
# lines below it, indented by 6; help2man makes a tagged paragraph of it only
# when indented by 20 or more, hence the sed.
wrapper() {  # NAME ARGS...: a program "NAME" running `gonio ARGS... "$@"`
  local name=$1
  shift
  printf '#!/bin/sh\n"%s" %s "$@" | sed "s/^      \\([^ ]\\)/                        \\1/"\n' \
    "$gonio" "$*" > "$work/$name"
  chmod +x "$work/$name"
}

see_also() {  # the SEE ALSO section, naming every page but $1
  local page=$1 list=() c
  [[ $page != gonio ]] && list+=(".BR gonio (1)")
  for c in "${commands[@]}"; do
    [[ $page != "gonio-$c" ]] && list+=(".BR gonio-$c (1)")
  done
  printf '[SEE ALSO]\n'
  local i
  for ((i = 0; i < ${#list[@]}; ++i)); do
    if ((i + 1 < ${#list[@]})); then printf '%s,\n' "${list[i]}"; else printf '%s\n' "${list[i]}"; fi
  done
}

page() {  # NAME SUMMARY
  local name=$1 summary=$2
  see_also "$name" > "$work/$name.h2m"
  # C.UTF-8: the help texts hold UTF-8 (·, °, ′), which help2man otherwise mangles.
  LC_ALL=C.UTF-8 "$help2man" --locale=C.UTF-8 --no-info --section=1 --version-string="$version" \
    --name="$summary" --include="$work/$name.h2m" --output="$work/$name.1" "$work/$name"
  gzip -9n < "$work/$name.1" > "$out/man1/$name.1.gz.tmp"
  mv "$out/man1/$name.1.gz.tmp" "$out/man1/$name.1.gz"
}

wrapper gonio
page gonio "a virtual goniophotometer"
for i in "${!commands[@]}"; do
  wrapper "gonio-${commands[i]}" "${commands[i]}"
  page "gonio-${commands[i]}" "${summaries[i]}"
done
