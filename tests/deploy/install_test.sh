#!/usr/bin/env bash
# deploy/install.sh without installing anything: the scripts parse, `--dry-run` changes nothing
# and shows the install with its prefix and data dir written into the systemd unit, the config and
# the nginx site; mobotd reads the rendered config and makes a token from it; systemd-analyze
# accepts the unit and nginx -t the site, each where the tool is there (skipped, and said so,
# where not: nothing is installed for this test).
#
#   tests/deploy/install_test.sh [PATH_TO_MOBOTD]   (default build/server/mobotd)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
MOBOTD="${1:-$ROOT/build/server/mobotd}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT

passed=0
failed=0
skipped=0
ok() { echo "ok: $*"; passed=$((passed + 1)); }
not_ok() { echo "FAILED: $*" >&2; failed=$((failed + 1)); }
skip() { echo "skipped: $*"; skipped=$((skipped + 1)); }
check() {
  local what="$1"
  shift
  if "$@"; then ok "$what"; else not_ok "$what"; fi
}
# The text between "----- begin PATH" and "----- end PATH" of the dry run's output.
written() {
  sed -n "\\|^----- begin $1\$|,\\|^----- end $1\$|p" "$TMP/dry-run.txt" | sed '1d;$d'
}

for script in "$ROOT"/deploy/*.sh; do
  check "bash -n $(basename "$script")" bash -n "$script"
done
if command -v shellcheck >/dev/null 2>&1; then
  check "shellcheck install.sh" shellcheck "$ROOT/deploy/install.sh"
else
  skip "shellcheck is not installed"
fi
check "install.sh refuses an unknown argument" \
  bash -c "! '$ROOT/deploy/install.sh' --dry-run --frobnicate >/dev/null 2>&1"
check "install.sh refuses a relative prefix" \
  bash -c "! '$ROOT/deploy/install.sh' --dry-run --prefix opt >/dev/null 2>&1"

prefix="$TMP/opt/mobot"
data="$TMP/var/lib/mobot"
"$ROOT/deploy/install.sh" --dry-run --prefix "$prefix" --data-dir "$data" \
  --nginx robot.example.com --nginx-cert "$TMP/tls/cert.pem" --nginx-key "$TMP/tls/key.pem" \
  >"$TMP/dry-run.txt" 2>&1 || { cat "$TMP/dry-run.txt"; not_ok "install.sh --dry-run exits 0"; }
check "the dry run changes nothing" bash -c "[[ ! -e '$TMP/opt' && ! -e '$TMP/var' ]]"
check "the dry run builds with the project's scripts" \
  grep -qF "+ $ROOT/deploy/build.sh" "$TMP/dry-run.txt"
check "the dry run installs the binary under the prefix" \
  grep -qF "+ install -m 0755 $ROOT/build/server/mobotd $prefix/bin/mobotd" "$TMP/dry-run.txt"
check "the dry run makes the data dir the mobot user's" \
  grep -qF "+ install -d -m 0750 -o mobot -g mobot $data" "$TMP/dry-run.txt"
check "the dry run makes the first admin token with mobotd token create" \
  grep -qE "^\+ runuser -u mobot -- $prefix/bin/mobotd token create .*--role admin" \
  "$TMP/dry-run.txt"

written /etc/systemd/system/mobotd.service >"$TMP/mobotd.service"
unit="$TMP/mobotd.service"
check "the unit runs the installed binary with the installed config and data dir" grep -qxF \
  "ExecStart=$prefix/bin/mobotd --config $prefix/etc/mobotd.yaml --data-dir $data" "$unit"
for line in "Restart=on-failure" "User=mobot" "NoNewPrivileges=yes" "ProtectSystem=strict" \
  "ReadWritePaths=$data" "ProtectHome=yes" "PrivateTmp=yes" "CapabilityBoundingSet=" \
  "SupplementaryGroups=dialout video"; do
  check "the unit has $line" grep -qxF "$line" "$unit"
done
check "the unit restarts after a pause" grep -qE "^RestartSec=[0-9]+s$" "$unit"

written "$prefix/etc/mobotd.yaml" >"$TMP/mobotd.yaml"
check "the config keeps its data in the data dir" grep -qxF "  data_dir: $data" "$TMP/mobotd.yaml"
check "the config serves the installed dashboard" \
  grep -qxF "  web_dir: $prefix/share/mobot/web" "$TMP/mobotd.yaml"
check "the config finds the installed worlds" \
  grep -qxF "  worlds_dir: $prefix/share/mobot/worlds" "$TMP/mobotd.yaml"

if [[ -x "$MOBOTD" ]]; then
  # The rendered config, with the data dir moved into the test's own space.
  sed "s|^  data_dir: .*|  data_dir: $TMP/data|" "$TMP/mobotd.yaml" >"$TMP/check.yaml"
  token="$("$MOBOTD" token create --config "$TMP/check.yaml" --label install-test --role admin \
    2>"$TMP/token.err" || true)"
  check "mobotd reads the rendered config and makes a token in its data dir" \
    bash -c "[[ '$token' =~ ^[0-9a-f]{64}$ && -f '$TMP/data/mobot.sqlite' ]]"
  [[ "$token" =~ ^[0-9a-f]{64}$ ]] || cat "$TMP/token.err" >&2
else
  skip "no mobotd at $MOBOTD: the rendered config is not loaded"
fi

if command -v systemd-analyze >/dev/null 2>&1 && [[ -x "$MOBOTD" ]]; then
  # verify wants the binary that ExecStart names.
  mkdir -p "$prefix/bin"
  ln -s "$MOBOTD" "$prefix/bin/mobotd"
  # Unknown or misspelt keys are only warnings to verify: any word about the unit fails it.
  if verdict="$(systemd-analyze verify "$unit" 2>&1)" && ! grep -qF "mobotd.service" <<<"$verdict"; then
    ok "systemd-analyze verify accepts the unit"
  else
    not_ok "systemd-analyze verify: $verdict"
  fi
else
  skip "systemd-analyze (or mobotd) is not there: the unit is not verified"
fi

written /etc/nginx/sites-available/mobot.conf >"$TMP/mobot.conf"
site="$TMP/mobot.conf"
check "the site answers for the name given" grep -qE "server_name robot.example.com;" "$site"
check "the site uses the certificate given" grep -qF "ssl_certificate     $TMP/tls/cert.pem;" "$site"
check "the site proxies to mobotd on 127.0.0.1:8080" grep -qF "server 127.0.0.1:8080;" "$site"
# shellcheck disable=SC2016 # nginx's variables, not the shell's
check "the site upgrades the stream to a WebSocket" \
  grep -qF 'proxy_set_header Upgrade $http_upgrade;' "$site"
check "the site sends HSTS" grep -qF 'Strict-Transport-Security "max-age=31536000" always' "$site"
check "the site keeps tokens out of its access log" bash -c \
  "grep -q 'access_log .* mobot_no_query;' '$site' && ! grep -q '\\\$request[^_]' '$site'"
if command -v nginx >/dev/null 2>&1 && command -v openssl >/dev/null 2>&1; then
  mkdir -p "$TMP/tls" "$TMP/nginx/logs"
  openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj "/CN=robot.example.com" \
    -keyout "$TMP/tls/key.pem" -out "$TMP/tls/cert.pem" >/dev/null 2>&1
  # The site's logs go to a place of the test's own.
  sed "s|/var/log/nginx/|$TMP/nginx/logs/|" "$site" >"$TMP/nginx/mobot.conf"
  cat >"$TMP/nginx/nginx.conf" <<NGINX
pid $TMP/nginx/nginx.pid;
error_log $TMP/nginx/logs/error.log;
events {}
http {
    include $TMP/nginx/mobot.conf;
}
NGINX
  if verdict="$(nginx -t -p "$TMP/nginx" -c "$TMP/nginx/nginx.conf" 2>&1)"; then
    ok "nginx -t accepts the site"
  else
    not_ok "nginx -t: $verdict"
  fi
else
  skip "nginx (or openssl, for its test certificate) is not installed: the site is not checked"
fi

echo "$passed passed, $failed failed, $skipped skipped"
((failed == 0))
