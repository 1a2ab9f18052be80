#!/usr/bin/env bash
# Serves DIR with Debian's nginx on 127.0.0.1 as users serve 3D Tiles (gzip, ETags, keep-alive; HTTPS with HTTP/2
# given a certificate and its key), for sgbench's runs over http. Prints the URL base ("http://127.0.0.1:PORT") on
# stdout once it accepts connections, and the path of its access log on stderr (tab-separated: method, URI,
# status, connection, request on it, protocol, body bytes as sent, seconds). Stops on SIGTERM or SIGINT, or when
# its stdin, a pipe, closes (the program that started it is gone). Its files stay in the directory it names.
# With --max-age S every response may be kept S seconds (Cache-Control: max-age and Expires, nginx's `expires`);
# with --gzip-static a FILE.gz beside FILE is sent as FILE's gzip encoding (compressed once, as a CDN holds tiles)
# rather than FILE compressed for each request.
#   bench/serve-nginx.sh DIR [--tls CERT KEY] [--port P] [--max-age S] [--gzip-static]
set -euo pipefail
usage() { echo "usage: $0 DIR [--tls CERT.pem KEY.pem] [--port P] [--max-age S] [--gzip-static]" >&2; exit 2; }
[ $# -ge 1 ] || usage
[ -d "$1" ] || { echo "$0: '$1' is not a directory" >&2; exit 2; }
root=$(realpath "$1"); shift
cert="" key="" port="" expires="" static=""
while [ $# -gt 0 ]; do
  case $1 in
    --tls) [ $# -ge 3 ] || usage; cert=$(realpath "$2"); key=$(realpath "$3"); shift 3 ;;
    --port) [ $# -ge 2 ] || usage; port=$2; shift 2 ;;
    --gzip-static) static="gzip_static on;"; shift ;;
    --max-age)
      if [ $# -lt 2 ] || ! [[ $2 =~ ^[0-9]+$ ]]; then usage; fi
      expires="expires ${2}s;"; shift 2 ;;
    *) usage ;;
  esac
done
nginx=$(command -v nginx || echo /usr/sbin/nginx)  # Debian's is in /usr/sbin, not on a user's PATH
[ -x "$nginx" ] || { echo "$0: no nginx (Debian's package nginx)" >&2; exit 1; }
if [ -z "$port" ]; then
  port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
fi

dir=$(mktemp -d "${TMPDIR:-/tmp}/sgkit-serve-XXXXXX")
listen="127.0.0.1:$port" scheme=http tls=""
if [ -n "$cert" ]; then
  listen+=" ssl http2" scheme=https tls="ssl_certificate \"$cert\"; ssl_certificate_key \"$key\";"
fi
# One process (no workers dropping to another user who might not read DIR); every file under $dir.
cat > "$dir/nginx.conf" <<EOF
master_process off;
error_log "$dir/error.log";
pid "$dir/nginx.pid";
events { worker_connections 4096; }
http {
  include /etc/nginx/mime.types;
  default_type application/octet-stream;
  log_format sg escape=none '\$request_method\t\$request_uri\t\$status\t\$connection\t\$connection_requests\t\$server_protocol\t\$body_bytes_sent\t\$request_time';
  access_log "$dir/access.log" sg;
  client_body_temp_path "$dir/body"; proxy_temp_path "$dir/proxy"; fastcgi_temp_path "$dir/fastcgi";
  uwsgi_temp_path "$dir/uwsgi"; scgi_temp_path "$dir/scgi";
  sendfile on; etag on; keepalive_timeout 60s; keepalive_requests 1000;
  gzip on; gzip_types *; gzip_proxied any; gzip_vary on; gzip_min_length 256;
  server { listen $listen; $tls root "$root"; $expires $static }
}
EOF

exec 3<&0  # a background job's stdin is /dev/null: the watcher reads the script's through fd 3
"$nginx" -p "$dir" -c "$dir/nginx.conf" -g 'daemon off;' 2>>"$dir/error.log" &
pid=$!
watcher=""
stop() {
  kill -TERM "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  [ -z "$watcher" ] || kill "$watcher" 2>/dev/null || true
}
trap stop EXIT
trap 'exit 0' TERM INT

# Ready once nginx wrote its pid file (after its socket listens) and a connection is accepted.
for ((i = 0; ; i++)); do
  if ! kill -0 "$pid" 2>/dev/null; then
    echo "$0: nginx did not start:" >&2
    cat "$dir/error.log" >&2
    exit 1
  fi
  if [ "$(cat "$dir/nginx.pid" 2>/dev/null)" = "$pid" ] && (: <"/dev/tcp/127.0.0.1/$port") 2>/dev/null; then break; fi
  [ "$i" -lt 1000 ] || { echo "$0: nginx not accepting connections after 20 s" >&2; exit 1; }
  sleep 0.02
done
echo "$scheme://127.0.0.1:$port"
echo "$0: serving $root; access log $dir/access.log" >&2

if [ -p /dev/stdin ]; then  # a pipe: its closing stops the server (a terminal or /dev/null does not)
  (while read -r _ <&3; do :; done; kill -TERM "$$") &
  watcher=$!
fi
wait "$pid"
