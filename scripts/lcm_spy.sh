#!/usr/bin/env bash
# lcm-spy that decodes the cell's message types: scripts/lcm_spy.sh [LCM_URL]
#
# Debian's /usr/bin/lcm-spy launcher does not work here: it passes -Xincgc, which Java 17 rejects,
# and lcm-spy's charts need jchart2d (libjchart2d-java), which the launcher does not put on the
# class path. So start lcm.spy.Spy directly with lcm.jar, jchart2d.jar and our types jar
# (build/drivers/prepreg_lcmtypes.jar, built with the project when a JDK and liblcm-java are
# installed). Without a display (no $DISPLAY) it runs under xvfb-run, e.g. for screenshots.
# Default URL: the loopback bus of the fake-hardware run (udpm, ttl=0).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
url="${1:-udpm://239.255.76.67:7667?ttl=0}"
types_jar="${PREPREG_LCM_TYPES_JAR:-$root/build/drivers/prepreg_lcmtypes.jar}"

need() {  # file, Debian package
  if [[ ! -f "$1" ]]; then
    echo "lcm_spy.sh: $1 missing: $2" >&2
    exit 1
  fi
}
need /usr/share/java/lcm.jar "apt-get install liblcm-java"
need /usr/share/java/jchart2d.jar "apt-get install libjchart2d-java"
need "$types_jar" "build it: cmake --build build --target prepreg_lcmtypes_jar (needs default-jdk-headless)"
command -v java >/dev/null || { echo "lcm_spy.sh: no java: apt-get install default-jre-headless" >&2; exit 1; }

cmd=(java -cp "/usr/share/java/lcm.jar:/usr/share/java/jchart2d.jar:$types_jar" lcm.spy.Spy
     --lcm-url="$url")
if [[ -z "${DISPLAY:-}" ]]; then
  command -v xvfb-run >/dev/null || { echo "lcm_spy.sh: no \$DISPLAY and no xvfb-run: apt-get install xvfb" >&2; exit 1; }
  # -a: first free display number; the screen is big enough for the channel table.
  exec xvfb-run -a -s "-screen 0 1280x800x24" "${cmd[@]}"
fi
exec "${cmd[@]}"
