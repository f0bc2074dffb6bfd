#!/usr/bin/env python3
"""Packs the built glintlab and glintlab_bench with the shared libraries they load into one
tar.gz that runs on another x86-64 Linux machine without Debian's packages: a GPU machine that
reaches no package registry and takes at most 64 MiB with a command.

The libraries' closure is about 365 MB, because Debian's OpenImageIO links every image and video
format it can read (FFmpeg, OpenCV, DCMTK, OpenVDB, HEIF, LibRaw, ...). glintlab reads and writes
EXR, PNG and HDR, so those format libraries are replaced by stubs: a library of the same soname
that defines, with the same symbol versions, exactly the symbols the kept libraries import from it;
each function traps (ud2), but constructors and destructors return at once (OpenImageIO's static
initialisers construct DCMTK objects) and C functions named for a version return "stub" (its plugin
catalogue asks every library for its version); objects are zero-filled. The kept libraries are
linked with BIND_NOW, so a missing symbol fails at load, and a call into a stub stops the process
with SIGILL. LibTIFF and FreeType stay real: the catalogue opens a TIFF reader, and the contact
sheet's labels are drawn with FreeType. glibc stays the machine's own (the version the bundle needs
is printed and checked by run.sh); libstdc++ and libgcc_s go into lib-fallback/, used only where the
machine's are older than the ones the binaries were built against. libglintlab_oiio.so,
libglintlab_ocio.so and libglintlab_glslang.so, which the programs load with dlopen when they first
read or write an image through OpenImageIO (core/util/oiio_plugin.h), load a colour configuration
(core/util/ocio_plugin.h) or compile a shader (core/vk/glslang_plugin.h), go into lib/ with their
closures.

    tests/bench/gpu_bundle.py [--build build] [--out .gpu] [--debs] [--check]

writes OUT/glintlab-gpu.tar.gz (bin/, lib/, lib-fallback/, run.sh, and share/glintlab/: the shaders,
experiments and OCIO config as `cmake --install` puts them, which the programs find beside
bin/). --debs also downloads into OUT/debs/ the
Vulkan loader and the GL vendor-neutral dispatch packages that an NVIDIA driver's Vulkan ICD needs
where the machine has no loader. --check unpacks the bundle into a temporary folder, checks with
the dynamic loader (`ld.so --list`) that every library but glibc's resolves inside it, and runs
`glintlab_bench --smoke` and a two-frame `glintlab run default` (report included) through run.sh.
On the machine:

    for f in .gpu/debs/*.deb; do dpkg -x $f /; done; ldconfig    # only where no loader is there
    tar xzf .gpu/glintlab-gpu.tar.gz -C /tmp
    /tmp/glintlab-gpu/run.sh glintlab_bench --device nvidia
    /tmp/glintlab-gpu/run.sh glintlab run default --device nvidia --out /tmp/default
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tarfile
import tempfile

# sonames left to the machine (glibc) and those kept as a fallback only
SYSTEM = {"libc.so.6", "libm.so.6", "libmvec.so.1", "libpthread.so.0", "libdl.so.2", "librt.so.1",
          "ld-linux-x86-64.so.2", "libresolv.so.2", "libutil.so.1", "libanl.so.1"}
FALLBACK = {"libstdc++.so.6", "libgcc_s.so.1"}
# OpenImageIO's format libraries glintlab never calls (it reads and writes EXR, PNG and HDR), and the
# OpenCV modules beside the three that DIS optical flow runs on (core, imgproc, video: `measure`)
STUB = re.compile(r"^lib(opencv_(?!(core|imgproc|video)\.so)|dcm|oflog|ofstd|i2d|avcodec|avformat|avutil|avdevice|avfilter|swscale|"
                  r"swresample|postproc|heif|openvdb|raw|raw_r|gif|openjp2|webp|webpdemux|webpmux|sharpyuv|"
                  r"gdal)[^/]*\.so")
PROGRAMS = ["glintlab", "glintlab_bench"]
# Loaded with dlopen (core/util/oiio_plugin.h, ocio_plugin.h, core/vk/glslang_plugin.h): found in lib/
# by --library-path.
PLUGINS = ["libglintlab_oiio.so", "libglintlab_ocio.so", "libglintlab_glslang.so"]
# Opened with dlopen by name, not named by any ELF: the Vulkan loader (core/vk/vulkan_functions.h).
DLOPENED = ["libvulkan.so.1"]
CTOR_DTOR = re.compile(r"^_ZN.*(C[123]|D[012])E")  # Itanium-mangled constructors and destructors


def run(cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout


def soname_paths():
    paths = {}
    # /sbin is not on an ordinary user's PATH on Debian
    ldconfig = shutil.which("ldconfig") or "/sbin/ldconfig"
    for line in run([ldconfig, "-p"]).splitlines():
        m = re.match(r"\s*(\S+) \(([^)]*)\) => (\S+)", line)
        if m and "x86-64" in m.group(2) and m.group(1) not in paths:
            paths[m.group(1)] = m.group(3)
    return paths


def needed(path):
    return re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", run(["readelf", "-dW", path]))


def dyn_symbols(path):
    """(name, version or None, defined, type, bind, size) of every dynamic symbol."""
    out = []
    for line in run(["readelf", "--dyn-syms", "-W", path]).splitlines():
        f = line.split()
        if len(f) < 8 or not f[0].endswith(":") or not f[0][:-1].isdigit():
            continue
        size = int(f[2], 0) if f[2].startswith("0x") else int(f[2])
        typ, bind, ndx, full = f[3], f[4], f[6], f[7]
        name, _, ver = full.partition("@")
        ver = ver.lstrip("@") or None
        out.append((name, ver, ndx != "UND", typ, bind, size))
    return out


def make_stub(soname, real_path, imports, out_dir, work):
    """A library named `soname` defining what the kept objects import from `real_path`."""
    defined = {}
    for name, ver, is_def, typ, bind, size in dyn_symbols(real_path):
        if is_def and name:
            defined.setdefault(name, (typ, bind, size))
    wanted = {}  # name -> its version (a name is defined once, in one version node)
    for name, ver in sorted(imports, key=lambda nv: (nv[0], nv[1] or "")):
        if name in defined and (name not in wanted or wanted[name] is None):
            wanted[name] = ver
    asm, versions = [], {}
    for name, ver in sorted(wanted.items()):
        typ, bind, size = defined[name]
        if ver:
            versions.setdefault(ver, set()).add(name)
        binding = ".weak" if bind == "WEAK" else ".globl"
        if typ in ("OBJECT", "TLS"):
            section = '.section .tbss,"awT",@nobits' if typ == "TLS" else ".bss"
            kind = "@tls_object" if typ == "TLS" else "@object"
            asm += [section, ".balign 16", f"{binding} {name}", f".type {name}, {kind}",
                    f".size {name}, {max(size, 1)}", f"{name}:", f".zero {max(size, 1)}"]
        else:  # a trap, but for constructors, destructors and version queries (see the top)
            if CTOR_DTOR.match(name):
                body = ["ret"]
            elif not name.startswith("_Z") and "version" in name.lower():
                body = ["leaq stub_version(%rip), %rax", "ret"]
            else:
                body = ["ud2"]
            asm += [".text", f"{binding} {name}", f".type {name}, @function", f"{name}:"] + body
    asm += [".section .rodata", "stub_version:", '.asciz "stub"']
    s_file = os.path.join(work, soname + ".s")
    with open(s_file, "w") as f:
        f.write("\n".join(asm) + "\n")
    cmd = ["gcc", "-shared", "-nostdlib", "-o", os.path.join(out_dir, soname), f"-Wl,-soname,{soname}", s_file]
    if versions:
        v_file = os.path.join(work, soname + ".map")
        with open(v_file, "w") as f:
            for ver, names in sorted(versions.items()):
                f.write(ver + " { global: " + " ".join(n + ";" for n in sorted(names)) + " };\n")
        cmd.append(f"-Wl,--version-script={v_file}")
    run(cmd)
    return len(wanted)


def max_version(paths, prefix):
    """The highest version `prefix`_x.y.z that one of `paths` requires (its version needs)."""
    best = (0,)
    for p in paths:
        text = run(["readelf", "-VW", p])
        needs = text[text.find("Version needs section"):] if "Version needs section" in text else ""
        for v in re.findall(r"Name: " + prefix + r"_([0-9.]+)", needs):
            best = max(best, tuple(int(x) for x in v.split(".")))
    return ".".join(map(str, best))


RUN_SH = r"""#!/bin/sh
# Runs a program of this bundle: run.sh glintlab|glintlab_bench [ARGS...] (tests/bench/gpu_bundle.py).
set -e
here=$(cd "$(dirname "$0")" && pwd)
prog=$1; shift
glibc=$(getconf GNU_LIBC_VERSION | cut -d' ' -f2)
if [ "$(printf '%s\n%s\n' "$(cat "$here/needs-glibc")" "$glibc" | sort -V | head -n1)" != "$(cat "$here/needs-glibc")" ]; then
  echo "run.sh: glibc $glibc is older than the $(cat "$here/needs-glibc") this bundle needs" >&2; exit 2
fi
libs=$here/lib
ldconfig=$(command -v ldconfig || echo /sbin/ldconfig)
sys_cxx=$("$ldconfig" -p | sed -n 's/.*libstdc++\.so\.6 (libc6,x86-64) => //p' | head -n1)
if [ -z "$sys_cxx" ] || ! grep -qa "GLIBCXX_$(cat "$here/needs-glibcxx")" "$sys_cxx"; then libs=$libs:$here/lib-fallback; fi
export XDG_CACHE_HOME=${XDG_CACHE_HOME:-/tmp/glintlab-cache}
nv=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json  # where the GPU machines keep NVIDIA's ICD
if [ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ] && [ -f "$nv" ]; then export VK_DRIVER_FILES=$nv; fi
# Started by the loader, a program's /proc/self/exe is the loader: the data folder is named here.
export GLINTLAB_DATA_DIR=${GLINTLAB_DATA_DIR:-$here/share/glintlab}
# The libraries through the loader's --library-path, not LD_LIBRARY_PATH: the report's Python,
# which glintlab starts, must not load the stubs in place of its own image libraries.
exec /lib64/ld-linux-x86-64.so.2 --library-path "$libs" "$here/bin/$prog" "$@"
"""


def build(args):
    paths = soname_paths()
    programs = [os.path.join(args.build, p) for p in PROGRAMS]
    plugins = [os.path.join(args.build, p) for p in PLUGINS]
    for p in programs + plugins:
        if not os.path.isfile(p):
            sys.exit(f"gpu_bundle: {p} not found: build first (cmake --build {args.build})")
    stage = tempfile.mkdtemp(prefix="glintlab-gpu-")
    top = os.path.join(stage, "glintlab-gpu")
    for d in ("bin", "lib", "lib-fallback", "work"):
        os.makedirs(os.path.join(top, d))
    # the closure, stopping at stubs and the system's libraries
    kept, stubs, queue = {}, {}, [n for p in programs + plugins for n in needed(p)] + DLOPENED
    while queue:
        so = queue.pop()
        if so in SYSTEM or so in kept or so in stubs:
            continue
        if so not in paths:
            sys.exit(f"gpu_bundle: {so} is not in the loader cache (ldconfig -p)")
        if STUB.match(so):
            stubs[so] = paths[so]
            continue
        kept[so] = paths[so]
        queue += needed(paths[so])
    objects = programs + plugins + list(kept.values())
    imports = set()
    for o in objects:
        imports |= {(n, v) for n, v, d, *_ in dyn_symbols(o) if not d and n}
    for p in programs:
        shutil.copy2(p, os.path.join(top, "bin"))
    for p in plugins:
        shutil.copy2(p, os.path.join(top, "lib"))
    for so, path in sorted(kept.items()):
        shutil.copy2(path, os.path.join(top, "lib-fallback" if so in FALLBACK else "lib", so))
    n_syms = sum(make_stub(so, path, imports, os.path.join(top, "lib"), os.path.join(top, "work"))
                 for so, path in sorted(stubs.items()))
    shutil.rmtree(os.path.join(top, "work"))
    # the data, in share/glintlab/ beside bin/ where the programs look for it (core/util/data_dir.h)
    subprocess.run(["cmake", "--install", args.build, "--prefix", top], check=True, capture_output=True)
    shutil.rmtree(os.path.join(top, "lib", "python3"), ignore_errors=True)  # the Python module: not used there
    with open(os.path.join(top, "needs-glibc"), "w") as f:
        f.write(max_version(objects, "GLIBC") + "\n")
    with open(os.path.join(top, "needs-glibcxx"), "w") as f:
        f.write(max_version(objects, "GLIBCXX") + "\n")
    with open(os.path.join(top, "run.sh"), "w") as f:
        f.write(RUN_SH)
    os.chmod(os.path.join(top, "run.sh"), 0o755)
    os.makedirs(args.out, exist_ok=True)
    tar = os.path.join(args.out, "glintlab-gpu.tar.gz")
    with tarfile.open(tar + ".tmp", "w:gz") as t:
        t.add(top, arcname="glintlab-gpu")
    os.replace(tar + ".tmp", tar)
    raw = sum(os.path.getsize(os.path.join(dp, f)) for dp, _, fs in os.walk(top) for f in fs)
    shutil.rmtree(stage)
    print(f"{tar}: {os.path.getsize(tar) / 2**20:.1f} MiB ({raw / 2**20:.1f} MiB unpacked); {len(kept)} libraries "
          f"kept, {len(stubs)} stubbed ({n_syms} symbols): {' '.join(sorted(stubs))}; needs glibc >= "
          f"{max_version(objects, 'GLIBC')}, libstdc++ with GLIBCXX_{max_version(objects, 'GLIBCXX')}")
    return tar


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default="build", help="the build folder (default: build)")
    ap.add_argument("--out", default=".gpu", help="output folder (default: .gpu)")
    ap.add_argument("--debs", action="store_true", help="also download the Vulkan loader and GLVND packages")
    ap.add_argument("--check", action="store_true", help="run the bundle here and check where libraries come from")
    args = ap.parse_args()
    tar = build(args)
    if args.debs:
        debs = os.path.join(args.out, "debs")
        os.makedirs(debs, exist_ok=True)
        subprocess.run(["apt-get", "download", "libvulkan1", "libglvnd0", "libegl1", "libgl1", "libglx0", "libgles2",
                        "libopengl0"], cwd=debs, check=True)
        print(f"{debs}: {' '.join(sorted(os.listdir(debs)))}")
    if args.check:
        check(tar)


def check(tar):
    """Unpacks the bundle and runs it here; exits 1 on a problem."""
    tmp = tempfile.mkdtemp(prefix="glintlab-gpu-check-")
    try:
        with tarfile.open(tar) as t:
            t.extractall(tmp)
        top = os.path.join(tmp, "glintlab-gpu")
        lib = os.path.join(top, "lib") + ":" + os.path.join(top, "lib-fallback")
        problems = []
        for prog in PROGRAMS:
            listing = run(["/lib64/ld-linux-x86-64.so.2", "--library-path", lib, "--list", os.path.join(top, "bin", prog)])
            for line in listing.splitlines():
                m = re.match(r"\s*(\S+) => (\S+)", line)
                if m and m.group(1) not in SYSTEM and not m.group(2).startswith(top + "/"):
                    problems.append(f"{prog}: {m.group(1)} resolves to {m.group(2)}, outside the bundle")
        env = {k: v for k, v in os.environ.items() if k not in ("LD_LIBRARY_PATH", "GLINTLAB_VALIDATION")}
        env.setdefault("XDG_CACHE_HOME", os.path.join(tmp, "cache"))  # the caller's shader caches, if any
        runs = [["glintlab_bench", "--smoke"],
                ["glintlab", "run", "default", "--frames", "2", "--out", os.path.join(tmp, "run"), "--cache",
                 os.path.join(tmp, "refs")]]
        for r in runs:
            p = subprocess.run([os.path.join(top, "run.sh")] + r, env=env, capture_output=True, text=True)
            if p.returncode != 0:
                problems.append(f"run.sh {' '.join(r)}: exit status {p.returncode}\n{p.stdout[-2000:]}{p.stderr[-2000:]}")
            else:
                print(f"check: run.sh {' '.join(r)}: ok")
        for f in ("summary.json", "frames.csv", "report.html"):
            if not os.path.isfile(os.path.join(tmp, "run", f)):
                problems.append(f"run.sh glintlab run default wrote no {f}")
        if problems:
            sys.exit("gpu_bundle: check failed:\n  " + "\n  ".join(problems))
        print("check: every library but glibc's resolves inside the bundle; both programs ran")
    finally:
        shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
