#!/bin/bash
# Builds rigd's .deb with CPack and installs it into a scratch root (dpkg-deb -x: files only,
# maintainer scripts are checked, not run, so nothing touches this machine's users or units),
# then checks the layout, the control data and that the installed binaries and unit work.
# usage: check_package.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$1"; src="$2"
fail() { echo "FAIL: $*"; exit 1; }
for t in rigd rig rig-sim; do [ -x "$build/bin/$t" ] || fail "$build/bin/$t not built (./rig test builds it)"; done
[ -f "$build/web-root/index.html" ] || fail "web page not built (target web_assets)"
rm -rf "$build/package"
(cd "$build" && cpack -G DEB --config CPackConfig.cmake >/dev/null) || fail "cpack failed"
deb="$(ls "$build"/package/rigd_*_amd64.deb)" || fail "no .deb produced"
echo "package: $deb ($(du -h "$deb" | cut -f1))"
dpkg-deb -I "$deb" > "$build/package/control.txt"
grep -q '^ Package: rigd$' "$build/package/control.txt" || fail "control: Package"
grep -q '^ Depends:.*libmodbus5' "$build/package/control.txt" || fail "control: Depends lacks libmodbus5 (shlibdeps)"
root="$(mktemp -d "${TMPDIR:-/tmp}/rigd-root.XXXXXX")"; trap 'rm -rf "$root"' EXIT
dpkg-deb -x "$deb" "$root"
dpkg-deb -e "$deb" "$root/DEBIAN"
for f in usr/sbin/rigd usr/bin/rig usr/bin/rig-sim usr/lib/systemd/system/rigd.service usr/lib/sysusers.d/rigd.conf \
         usr/lib/udev/rules.d/60-rigd.rules etc/rigd/rigd.toml usr/share/rigd/web/index.html usr/share/rigd/web/app.js \
         usr/share/rigd/web/vendor/uPlot.iife.min.js usr/share/rigd/web/vendor/three.module.js usr/share/rigd/web/vendor/three.core.js \
         usr/share/rigd/web/cornea3d.js usr/share/rigd/web/lab_plots.js usr/share/rigd/models/paper-interpreted.toml \
         usr/share/rigd/models/paper-printed-without-k.toml \
         usr/share/doc/rigd/technician-guide.md usr/share/doc/rigd/deployment.md; do
  [ -e "$root/$f" ] || fail "/$f missing from the package"
done
[ -x "$root/DEBIAN/postinst" ] || fail "postinst missing or not executable"
grep -qx '/etc/rigd/rigd.toml' "$root/DEBIAN/conffiles" || fail "/etc/rigd/rigd.toml is not a conffile (an upgrade would overwrite the lab's config)"
grep -q 'systemd-sysusers rigd.conf' "$root/DEBIAN/postinst" || fail "postinst does not create the rigd user"
sh -n "$root/DEBIAN/postinst" && sh -n "$root/DEBIAN/prerm" || fail "maintainer script syntax"
# Installed pieces work together: the packaged rigd accepts the packaged config ...
"$root/usr/sbin/rigd" --check-config --config "$root/etc/rigd/rigd.toml" || fail "packaged rigd rejects the packaged config"
# ... and the packaged unit verifies when pointed at the packaged binary.
sed "s|/usr/sbin/rigd|$root/usr/sbin/rigd|g; s|/etc/rigd/|$root/etc/rigd/|g" "$root/usr/lib/systemd/system/rigd.service" > "$root/rigd.service"
out="$(systemd-analyze verify "$root/rigd.service" 2>&1)" || fail "systemd-analyze verify: $out"
[ -z "$out" ] || fail "systemd-analyze verify: $out"
# ... and the packaged `rig` writes a model-lab report from the install paths alone (the page's
# assets in /usr/share/rigd/web beside /usr/bin/rig), without RIG_WEB_ROOT.
report="$root/report.html"
env -u RIG_WEB_ROOT -u RIG_MODEL_DIR "$root/usr/bin/rig" model compare "$src/tests/data/okamura2004-needle/needle-liver-insert-hold-retract.csv" \
  --report "$report" > /dev/null 2>&1 || fail "the packaged rig could not write a report"
grep -q 'function rigLabPlots' "$report" && grep -q '"series"' "$report" || fail "the packaged report lacks its plots or data"
echo "installed into $root: $(find "$root" -type f | wc -l) files; layout, control data, config and unit OK"
