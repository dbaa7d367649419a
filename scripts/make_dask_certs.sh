#!/bin/bash
# Makes the certificates for a Dask cluster with TLS (docs/CLUSTER.md): a CA, and a certificate and key signed
# by it for the scheduler, for the workers and for the client (`hako run --scheduler tls://...`).
#
# Usage: scripts/make_dask_certs.sh OUT_DIR [HOST...]
#   OUT_DIR gets ca.pem (give it to every side), ca.key (keep it apart: it signs more certificates), and
#   scheduler.pem/.key, worker.pem/.key, client.pem/.key. Each certificate names the HOSTs (default
#   127.0.0.1 and localhost) as its subject's alternative names, for a client that checks them.
#   Valid for 365 days; RSA 2048. Needs openssl (apt-get install openssl).
set -euo pipefail
die() { echo "make_dask_certs: $*" >&2; exit 1; }
[ $# -ge 1 ] || die "usage: scripts/make_dask_certs.sh OUT_DIR [HOST...]"
command -v openssl > /dev/null || die "openssl is not installed: apt-get install openssl"
out=$1; shift
hosts=("${@:-127.0.0.1}")
[ $# -ge 1 ] || hosts+=(localhost)
san=""
for h in "${hosts[@]}"; do
  if [[ $h =~ ^[0-9.]+$ || $h == *:* ]]; then san+="IP:$h,"; else san+="DNS:$h,"; fi
done
mkdir -p "$out"
cd "$out"
openssl req -x509 -newkey rsa:2048 -nodes -keyout ca.key -out ca.pem -days 365 -subj "/CN=hakoniwa-py Dask CA" \
  2> /dev/null || die "openssl could not make the CA in $out"
for role in scheduler worker client; do
  openssl req -newkey rsa:2048 -nodes -keyout "$role.key" -out "$role.csr" -subj "/CN=hakoniwa-py Dask $role" \
    2> /dev/null || die "openssl could not make the $role key in $out"
  openssl x509 -req -in "$role.csr" -CA ca.pem -CAkey ca.key -CAcreateserial -out "$role.pem" -days 365 \
    -extfile <(printf 'subjectAltName=%s\n' "${san%,}") 2> /dev/null || die "openssl could not sign the $role certificate"
  rm "$role.csr"
done
chmod 600 ./*.key
echo "$out: ca.pem, scheduler.pem/.key, worker.pem/.key, client.pem/.key"
