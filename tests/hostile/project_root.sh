#!/bin/bash
# Files named inside input files stay in the project root: the git work tree holding the input,
# else its folder; --root names another, --allow-outside-root lifts the limit. A vault in
# project/vaults/ naming ../lib (a sibling folder) shows each case.
set -u
sscs=$(realpath "$1") root=$(realpath "$2")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
mkdir -p "$dir/project/vaults" "$dir/project/lib/types"
cp "$root/library/types/drum.yaml" "$dir/project/lib/types/mydrum.yaml"
sed -i 's/^type: drum$/type: mydrum/' "$dir/project/lib/types/mydrum.yaml"
printf 'sscs: 1\nvault: V\nlibrary: [../lib]\nobjects:\n  - {type: mydrum, name: D}\n' > "$dir/project/vaults/v.yaml"
fail() { echo "FAIL: $1"; cat "$dir/err"; exit 1; }
cd "$dir/project/vaults"

# No git work tree: the root is the vault's folder, and ../lib is outside it.
"$sscs" check v.yaml >/dev/null 2>"$dir/err"; code=$?
[ $code = 2 ] || fail "exit $code outside the root, expected 2"
grep -q "v.yaml:3:11: error: type library folder '.*/lib' is outside the project root $dir/project/vaults" "$dir/err" ||
  fail "the message should name the folder and the root"

"$sscs" check v.yaml --root "$dir/project" >/dev/null 2>"$dir/err" || fail "--root holding the library should pass"
"$sscs" check v.yaml --allow-outside-root >/dev/null 2>"$dir/err" || fail "--allow-outside-root should pass"
# --library names a folder on the command line: trusted, like the standard library.
"$sscs" check v.yaml --library "$dir/project/lib" >/dev/null 2>"$dir/err" || fail "a --library folder is trusted"

# In a git work tree the root is its top: the project's own folders are in.
git init -q "$dir/project" 2>/dev/null || mkdir "$dir/project/.git"
"$sscs" check v.yaml >/dev/null 2>"$dir/err" || fail "inside a git work tree, ../lib is in the project"

# A symbolic link in the project pointing out of it is outside.
mkdir -p "$dir/elsewhere/types"
mv "$dir/project/lib/types/mydrum.yaml" "$dir/elsewhere/types/"
ln -s "$dir/elsewhere/types/mydrum.yaml" "$dir/project/lib/types/mydrum.yaml"
"$sscs" check v.yaml >/dev/null 2>"$dir/err"; code=$?
[ $code = 2 ] || fail "exit $code for a symlink out of the project, expected 2"
grep -q "type file '.*mydrum.yaml' leads outside the project root $dir/project through a symbolic link" "$dir/err" ||
  fail "the message should say the link leads out"
# check with several vaults: each reads within its own project (v.yaml's folder), not another's.
printf 'sscs: 1\nvault: O\nobjects: []\n' > "$dir/project/o.yaml"
rm "$dir/project/lib/types/mydrum.yaml"; mv "$dir/elsewhere/types/mydrum.yaml" "$dir/project/lib/types/"
rm -rf "$dir/project/.git"
"$sscs" check v.yaml ../o.yaml >/dev/null 2>"$dir/err"; code=$?
[ $code = 2 ] || fail "exit $code: o.yaml's project (which holds lib/) must not let v.yaml read ../lib, expected 2"
grep -q "v.yaml:3:11: error: type library folder" "$dir/err" || fail "the error should be v.yaml's"
"$sscs" check v.yaml --root "$dir/nowhere" >/dev/null 2>"$dir/err"; code=$?
[ $code = 2 ] && grep -q -- "--root '.*nowhere' is no folder" "$dir/err" || fail "a --root that is no folder is an error"

# A file a mesh refers to (a glTF buffer) that is a FIFO is refused, not waited on for ever.
mkdir -p "$dir/fifo/lib/types"
printf 'sscs: 1\nvault: F\nlibrary: [lib]\nobjects:\n  - {type: part, name: P}\n' > "$dir/fifo/v.yaml"
printf 'sscs: 1\ntype: part\ngeometry:\n  - mesh: {file: part.gltf}\n' > "$dir/fifo/lib/types/part.yaml"
sed 's|"uri":"[./a-z]*passwd"|"uri":"buffer.bin"|' "$root/tests/data/bad/libs/mesh_refers_outside_root/types/part.gltf" > "$dir/fifo/lib/types/part.gltf"
mkfifo "$dir/fifo/lib/types/buffer.bin"
timeout 60 "$sscs" check "$dir/fifo/v.yaml" >/dev/null 2>"$dir/err"; code=$?
[ $code = 2 ] && grep -q "it refers to '.*buffer.bin', which is a FIFO (named pipe), not a file" "$dir/err" ||
  fail "exit $code: a glTF buffer that is a FIFO must be refused"
# "sec/../x" goes where the system goes: through sec, a link to another folder of the project,
# then up from there (read lexically it named a file that does not exist).
mkdir -p "$dir/dots/real/sub" "$dir/dots/real/lib/types"
cp "$dir/project/lib/types/mydrum.yaml" "$dir/dots/real/lib/types/"
ln -s real/sub "$dir/dots/sec"
printf 'sscs: 1\nvault: D\nlibrary: [sec/../lib]\nobjects:\n  - {type: mydrum, name: D}\n' > "$dir/dots/v.yaml"
"$sscs" check "$dir/dots/v.yaml" >/dev/null 2>"$dir/err" || fail "sec/../lib through a link must be found where the system finds it"
echo "project root: the input's folder, its git work tree, --root, --library, --allow-outside-root and symlinks as documented"
