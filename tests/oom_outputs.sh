# SPDX-License-Identifier: MIT
# Sourced by test_cli_oom.sh and test_mpi_cli_oom.sh: the outputs of a run
# with nothing failing are in $work/ref, a run under test writes into
# $work/out (both set by the caller).

# Every file of ref in out with old bytes of its own
old_files() {
    local f
    for f in "$work/ref"/*; do
        printf 'an old %s\n' "${f##*/}" >"$work/out/${f##*/}"
    done
}

# out holds ref's names, each with its old bytes, nothing else
old_kept() {
    [ "$(ls -A "$work/ref")" = "$(ls -A "$work/out")" ] || return 1
    local f
    for f in "$work/ref"/*; do
        [ "$(cat "$work/out/${f##*/}")" = "an old ${f##*/}" ] || return 1
    done
}

# The same files in ref and out, the same bytes but in reports (.json: their
# paths, seconds and memory differ from run to run)
same_outputs() {
    [ "$(ls -A "$work/ref")" = "$(ls -A "$work/out")" ] || return 1
    local f
    for f in "$work/ref"/*; do
        case $f in
        *.json) ;;
        *) cmp -s "$f" "$work/out/${f##*/}" || return 1 ;;
        esac
    done
}
