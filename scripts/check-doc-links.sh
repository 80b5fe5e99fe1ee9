#!/usr/bin/env bash
# Checks that every relative link in README.md, CHANGELOG.md and docs/**/*.md names a file or
# folder that exists (anchors are not checked). Prints each broken link and exits 1 if any.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

status=0
while IFS= read -r -d '' file; do
    dir=$(dirname "$file")
    # Inline links and images: ](target) or ](target "title").
    while IFS= read -r target; do
        target=${target%% *}
        target=${target%%#*}
        case "$target" in
            ''|http://*|https://*|mailto:*) continue ;;
        esac
        if [[ ! -e "$dir/$target" ]]; then
            echo "$file: broken link: $target"
            status=1
        fi
    done < <(grep -o '](\([^)]*\))' "$file" | sed 's/^](\(.*\))$/\1/')
done < <(find README.md CHANGELOG.md docs -name '*.md' -print0 2>/dev/null)
if ((status == 0)); then
    echo "+ documentation links: all resolve"
fi
exit "$status"
