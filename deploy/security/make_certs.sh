#!/usr/bin/env bash
# Makes the files of DDS Security for a pipeline (dds.security_dir; docs/deploy.md, "Security on
# the link") with openssl alone:
#   identity_ca.pem, identity_ca.key        signs the participants' certificates
#   permissions_ca.pem, permissions_ca.key  signs the governance and permissions documents
#   governance.p7s      every domain 0-230: only authenticated participants join; discovery,
#                       liveliness, and every topic's data and metadata encrypted and signed
#   permissions.p7s     one grant per identity: publish and subscribe every topic and partition
#   NAME.pem, NAME.key  one identity per NAME (e.g. a, b: the hosts), CN=NAME
#
#   deploy/security/make_certs.sh DIR NAME [NAME...]
#
# Copy DIR to every host, or, better, only the CA certificates, the two .p7s and each host's own
# NAME.pem/NAME.key (the two .key files of the CAs need never leave the machine that made them).
# Certificates are valid for 10 years; EC prime256v1 keys; the keys are written mode 600.
set -euo pipefail
die() { echo "make_certs.sh: error: $*" >&2; exit 1; }
[ $# -ge 2 ] || { sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
DIR="$1"; shift
command -v openssl >/dev/null || die "openssl not installed"
for n in "$@"; do
  [[ "$n" =~ ^[A-Za-z0-9._:-]+$ ]] || die "identity name '$n': letters, digits and .-_: only"
  case "$n" in identity_ca|permissions_ca|governance|permissions) die "identity name '$n' is reserved" ;; esac
done
mkdir -p "$DIR" || die "cannot create '$DIR'"
cd "$DIR"
umask 077
key() { openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:prime256v1 -out "$1" 2>/dev/null || die "cannot make key $1"; }
for ca in identity_ca permissions_ca; do
  if [ ! -f $ca.pem ] || [ ! -f $ca.key ]; then
    key $ca.key
    openssl req -x509 -new -key $ca.key -out $ca.pem -days 3650 \
      -subj "/CN=DetectFusion ${ca%_ca} CA" 2>/dev/null || die "cannot make $ca.pem"
  fi
done
for n in "$@"; do
  key "$n.key"
  openssl req -new -key "$n.key" -out "$n.csr" -subj "/CN=$n" 2>/dev/null ||
    die "cannot make the request of $n"
  openssl x509 -req -in "$n.csr" -CA identity_ca.pem -CAkey identity_ca.key -CAcreateserial \
    -out "$n.pem" -days 3650 2>/dev/null || die "cannot sign the certificate of $n"
  rm -f "$n.csr"
done
umask 022
chmod 644 ./*.pem
# Cyclone 0.10 refuses a domain range above 230 in both documents.
cat > governance.xml <<'XML'
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>230</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
XML
# Every identity with a certificate in DIR gets a grant (so names added later keep the earlier).
{
  echo '<?xml version="1.0" encoding="UTF-8"?>'
  echo '<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">'
  echo '  <permissions>'
  for cert in *.pem; do
    n="${cert%.pem}"
    case "$n" in identity_ca|permissions_ca) continue ;; esac
    cat <<XML
    <grant name="$n">
      <subject_name>CN=$n</subject_name>
      <validity><not_before>2020-01-01T00:00:00</not_before><not_after>2099-01-01T00:00:00</not_after></validity>
      <allow_rule>
        <domains><id_range><min>0</min><max>230</max></id_range></domains>
        <publish><topics><topic>*</topic></topics><partitions><partition>*</partition></partitions></publish>
        <subscribe><topics><topic>*</topic></topics><partitions><partition>*</partition></partitions></subscribe>
      </allow_rule>
      <default>DENY</default>
    </grant>
XML
  done
  echo '  </permissions>'
  echo '</dds>'
} > permissions.xml
for doc in governance permissions; do
  openssl smime -sign -in $doc.xml -text -out $doc.p7s -signer permissions_ca.pem \
    -inkey permissions_ca.key || die "cannot sign $doc.xml"
done
echo "make_certs.sh: $(pwd): identities $(ls *.pem | grep -v _ca.pem | sed 's/\.pem$//' | tr '\n' ' ')"
