#!/usr/bin/env bash
# Installs mobotd as a system service on Debian, as root: builds it (setup.sh, build.sh), installs
# the binary, the dashboard, the simulator's worlds and a config under PREFIX (default
# /opt/mobot), creates the `mobot` system user and its data dir /var/lib/mobot, installs and
# starts the systemd unit (deploy/systemd/mobotd.service), optionally the nginx site for TLS in
# front (deploy/nginx/mobot.conf), and on the first install makes the first admin token with
# `mobotd token create` and prints it, once. Safe to run again: it upgrades the binary and the
# assets and keeps the config and the data. docs/deploy.md has the whole story.
#
#   deploy/install.sh [--prefix DIR] [--data-dir DIR] [--config FILE] [--nginx SERVER_NAME]
#                     [--nginx-cert FILE --nginx-key FILE] [--no-build] [--dry-run]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

prefix=/opt/mobot
data_dir=/var/lib/mobot
source_config="$ROOT/deploy/config/default.yaml"
nginx_name=""
nginx_cert=""
nginx_key=""
build=1
dry_run=0
user=mobot

usage() {
  sed -n '2,12p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
}

die() {
  echo "install.sh: $*" >&2
  exit 2
}

while (($#)); do
  case "$1" in
    --prefix) prefix="${2:?--prefix needs a directory}"; shift 2 ;;
    --data-dir) data_dir="${2:?--data-dir needs a directory}"; shift 2 ;;
    --config) source_config="${2:?--config needs a file}"; shift 2 ;;
    --nginx) nginx_name="${2:?--nginx needs the server name}"; shift 2 ;;
    --nginx-cert) nginx_cert="${2:?--nginx-cert needs a file}"; shift 2 ;;
    --nginx-key) nginx_key="${2:?--nginx-key needs a file}"; shift 2 ;;
    --no-build) build=0; shift ;;
    --dry-run) dry_run=1; shift ;;
    -h | --help) usage; exit 0 ;;
    *) die "unknown argument '$1' (--help lists them)" ;;
  esac
done

[[ "$prefix" == /* ]] || die "--prefix must be an absolute path, not '$prefix'"
[[ "$data_dir" == /* ]] || die "--data-dir must be an absolute path, not '$data_dir'"
[[ -f "$source_config" ]] || die "no config file '$source_config'"
if [[ -n "$nginx_name" && ! "$nginx_name" =~ ^[A-Za-z0-9.-]+$ ]]; then
  die "--nginx takes a host name (letters, digits, dots, dashes), not '$nginx_name'"
fi
nginx_cert="${nginx_cert:-/etc/letsencrypt/live/$nginx_name/fullchain.pem}"
nginx_key="${nginx_key:-/etc/letsencrypt/live/$nginx_name/privkey.pem}"
if ((!dry_run)) && [[ $(id -u) -ne 0 ]]; then
  die "run it as root (or with --dry-run to see what it would do)"
fi

bin_dir="$prefix/bin"
etc_dir="$prefix/etc"
share_dir="$prefix/share/mobot"
config="$etc_dir/mobotd.yaml"
unit_file=/etc/systemd/system/mobotd.service
site_file=/etc/nginx/sites-available/mobot.conf

# Every change goes through run (or write_file): --dry-run prints it instead.
run() {
  if ((dry_run)); then
    printf '+'
    printf ' %q' "$@"
    printf '\n'
  else
    "$@"
  fi
}

# write_file PATH MODE: the text on stdin becomes PATH.
write_file() {
  local path="$1" mode="$2" text
  text="$(cat)"
  if ((dry_run)); then
    echo "+ write $path (mode $mode):"
    echo "----- begin $path"
    printf '%s\n' "$text"
    echo "----- end $path"
  else
    printf '%s\n' "$text" >"$path.new"
    chmod "$mode" "$path.new"
    mv "$path.new" "$path"
  fi
}

step() { echo "== $*"; }

# The repository's files with the install's paths written over the defaults they name.
render_unit() {
  sed -e "s|/opt/mobot|$prefix|g" -e "s|/var/lib/mobot|$data_dir|g" \
    "$ROOT/deploy/systemd/mobotd.service"
}
render_config() {
  sed -e "s|^  data_dir: .*|  data_dir: $data_dir|" \
    -e "s|^  web_dir: .*|  web_dir: $share_dir/web|" \
    -e "s|^  worlds_dir: .*|  worlds_dir: $share_dir/worlds|" "$source_config"
}
render_site() {
  sed -e "s|/etc/letsencrypt/live/mobot.example.org/fullchain.pem|$nginx_cert|" \
    -e "s|/etc/letsencrypt/live/mobot.example.org/privkey.pem|$nginx_key|" \
    -e "s|mobot.example.org|$nginx_name|g" "$ROOT/deploy/nginx/mobot.conf"
}

if ((build)); then
  step "build (deploy/setup.sh, deploy/build.sh)"
  run "$ROOT/deploy/setup.sh"
  run "$ROOT/deploy/build.sh"
fi
if ((!dry_run)); then
  [[ -x "$ROOT/build/server/mobotd" ]] || die "no build/server/mobotd: build it first"
  [[ -f "$ROOT/web/dist/index.html" ]] || die "no web/dist: build the dashboard first"
fi

step "user $user and data dir $data_dir"
if ! id -u "$user" >/dev/null 2>&1; then
  run useradd --system --user-group --home-dir "$data_dir" --no-create-home \
    --shell /usr/sbin/nologin --comment "mobot robot server" "$user"
fi
run install -d -m 0750 -o "$user" -g "$user" "$data_dir"

step "files under $prefix"
run install -d -m 0755 "$bin_dir" "$etc_dir" "$share_dir" "$prefix/share/doc/mobot"
run install -m 0755 "$ROOT/build/server/mobotd" "$bin_dir/mobotd"
run rm -rf "$share_dir/web" "$share_dir/worlds"
run cp -r "$ROOT/web/dist" "$share_dir/web"
run cp -r "$ROOT/drivers/sim/worlds" "$share_dir/worlds"
run install -m 0644 "$ROOT/docs/deploy.md" "$ROOT/docs/api.md" "$prefix/share/doc/mobot/"
if [[ -f "$config" ]]; then
  echo "keeping $config (the new default is written next to it as mobotd.yaml.dist)"
  render_config | write_file "$config.dist" 0640
else
  render_config | write_file "$config" 0640
fi
# Readable by the service's group, not by everybody: a config may name the TLS key.
run chgrp "$user" "$config"

step "systemd unit $unit_file"
render_unit | write_file "$unit_file" 0644
if command -v systemd-analyze >/dev/null 2>&1; then
  run systemd-analyze verify "$unit_file"
fi

first_install=0
[[ -f "$data_dir/mobot.sqlite" ]] || first_install=1
if ((first_install)); then
  step "the first admin token"
  if ((dry_run)); then
    run runuser -u "$user" -- "$bin_dir/mobotd" token create --config "$config" \
      --label "first admin (install.sh)" --role admin
  else
    token="$(runuser -u "$user" -- "$bin_dir/mobotd" token create --config "$config" \
      --label "first admin (install.sh)" --role admin)"
  fi
fi

if [[ -d /run/systemd/system ]]; then
  step "start mobotd"
  run systemctl daemon-reload
  run systemctl enable mobotd.service
  run systemctl restart mobotd.service
else
  echo "systemd is not running here: start it with systemctl start mobotd on the robot"
fi

if [[ -n "$nginx_name" ]]; then
  step "nginx site $site_file for https://$nginx_name"
  if ! command -v nginx >/dev/null 2>&1; then
    run apt-get install -y -qq --no-install-recommends nginx
  fi
  render_site | write_file "$site_file" 0644
  run ln -sfn "$site_file" /etc/nginx/sites-enabled/mobot.conf
  if ((dry_run)) || { [[ -f "$nginx_cert" ]] && [[ -f "$nginx_key" ]]; }; then
    run nginx -t
    run systemctl reload nginx
  else
    echo "no certificate at $nginx_cert yet: get one (e.g. certbot certonly --webroot), then"
    echo "  nginx -t && systemctl reload nginx"
  fi
fi

if ((first_install)) && ((!dry_run)); then
  echo
  echo "The first admin token (shown only now; make more with: $bin_dir/mobotd token create):"
  echo "  $token"
  if [[ -n "$nginx_name" ]]; then
    echo "Dashboard: https://$nginx_name/?token=$token"
  else
    echo "Dashboard: http://127.0.0.1:8080/?token=$token"
  fi
fi
step "done"
