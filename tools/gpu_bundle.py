#!/usr/bin/env python3
"""Packs built nephele programs with the shared libraries they need into one folder, for a machine
that has a GPU driver but none of Debian 12's libraries (the lent NVIDIA machine: docs/benchmarks.md
"On an NVIDIA GPU"; tools/gpu_prepare.sh calls it).

Usage: tools/gpu_bundle.py OUTDIR PROGRAM... [--stub SONAME_PREFIX ...]

Every library in the programs' closure is copied (stripped) into OUTDIR/lib, except the C/C++
runtime and GL dispatch (glvnd) libraries, which the target machine has.  A library named by
--stub (a prefix of its soname, e.g. libgdal) is not copied: a stub with the same soname takes its
place, defining every symbol the objects that load it import from it (functions that return 0, or
an empty string where the name asks for a version; objects of the original's size; the symbol
versions the importers ask for), so the loader is satisfied without the library's own closure.
Use it only for libraries the run never calls (GDAL's database drivers, OpenImageIO's ffmpeg or
DICOM plug-ins for a run that writes PNG and EXR): a call does nothing and returns 0 (the static
registrations OpenImageIO's plug-ins make at load time run harmlessly).
"""
import argparse, functools, os, re, shutil, subprocess, sys

SYSTEM = re.compile(r"^(libc|libm|libstdc\+\+|libgcc_s|libdl|libpthread|librt|ld-linux-x86-64|libEGL|libGLX|"
                    r"libGLdispatch|libOpenGL|libGL)\.so")


def run(*cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout


@functools.lru_cache(maxsize=None)  # asked once per importer and stub
def needed(path):
    return re.findall(r"\(NEEDED\)\s+Shared library: \[(.+?)\]", run("readelf", "-d", path))


def resolve(path):
    """soname -> real path, as the loader here resolves them for `path`."""
    out = {}
    for line in run("ldd", path).splitlines():
        m = re.match(r"\s*(\S+) => (\S+)", line)
        if m and m.group(2) != "not":
            out[m.group(1)] = m.group(2)
    return out


def dynsyms(path, defined):
    """name -> (version or None, type letter, size) of the dynamic symbols."""
    args = ["nm", "-D", "-S", "--defined-only" if defined else "--undefined-only", path]
    out = {}
    for line in run(*args).splitlines():
        parts = line.split()
        if defined:
            if len(parts) == 4:
                _, size, kind, name = parts
            elif len(parts) == 3:
                _, kind, name = parts
                size = "0"
            else:
                continue
        else:
            kind, name, size = parts[-2], parts[-1], "0"
        ver = None
        if "@" in name:
            name, _, ver = name.partition("@")
            ver = ver.lstrip("@") or None
        out[name] = (ver, kind, int(size, 16))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("outdir")
    ap.add_argument("programs", nargs="+")
    ap.add_argument("--stub", action="append", default=[])
    a = ap.parse_args()
    lib = os.path.join(a.outdir, "lib")
    os.makedirs(lib, exist_ok=True)
    where = {}
    for p in a.programs:
        where.update(resolve(p))
    stubbed = lambda so: any(so.startswith(s) for s in a.stub)
    real, stubs, todo = [], set(), list(a.programs)
    seen = set(todo)
    while todo:
        obj = todo.pop()
        for so in needed(obj):
            if SYSTEM.match(so):
                continue
            if stubbed(so):
                stubs.add(so)
                continue
            path = where.get(so) or resolve(obj).get(so)
            if not path:
                sys.exit(f"gpu_bundle: {obj} needs {so}, which does not resolve here")
            if path not in seen:
                seen.add(path)
                real.append((so, path))
                todo.append(path)
    for so, path in real:
        dst = os.path.join(lib, so)
        shutil.copyfile(path, dst)
        subprocess.run(["strip", "--strip-unneeded", dst], check=False, capture_output=True)
    importers = list(a.programs) + [p for _, p in real]
    undefined = {imp: dynsyms(imp, False) for imp in importers}
    for so in sorted(stubs):
        # What the objects that name this soname import, with the versions they ask for (libcurl's
        # CURL_OPENSSL_4 and libcurl-gnutls' CURL_GNUTLS_4 export the same names).
        imports = {}
        for imp in importers:
            if so in needed(imp):
                for name, (ver, _, _) in undefined[imp].items():
                    imports.setdefault(name, ver)
        make_stub(so, where.get(so) or find_lib(so), imports, lib)
    total = sum(os.path.getsize(os.path.join(lib, f)) for f in os.listdir(lib))
    print(f"gpu_bundle: {len(real)} libraries, {len(stubs)} stubs ({', '.join(sorted(stubs))}), {total / 2**20:.1f} MiB")


def find_lib(so):
    for d in ("/lib/x86_64-linux-gnu", "/usr/lib/x86_64-linux-gnu", "/lib", "/usr/lib"):
        if os.path.exists(os.path.join(d, so)):
            return os.path.join(d, so)
    sys.exit(f"gpu_bundle: cannot find {so}")


def make_stub(so, original, imports, lib):
    defs = dynsyms(original, True)
    funcs, objs, versions = [], [], {}
    for name, (ver_ref, kind, size) in defs.items():  # ver_ref: the original's own
        if name not in imports:
            continue
        ver = imports[name] or ver_ref  # the version the importers ask for (aliases differ)
        if ver:
            versions.setdefault(ver, []).append(name)
        if kind in "TtWiI":
            funcs.append(name)
        else:
            objs.append((name, max(size, 8)))
    asm = [".text"]
    for f in funcs:
        body = "lea nephele_stub_zeros(%rip), %rax" if "version" in f.lower() else "xor %eax, %eax"
        asm += [f'.globl "{f}"', f'.type "{f}", @function', f'"{f}":', body, "ret"]
    asm += [".bss", ".balign 64", "nephele_stub_zeros:", ".zero 65536", ".data"]
    for o, size in objs:
        asm += [f'.globl "{o}"', f'.type "{o}", @object', f'.size "{o}", {size}', ".balign 16", f'"{o}":',
                f".zero {size}"]
    base = os.path.join(lib, so)
    with open(base + ".s", "w") as f:
        f.write("\n".join(asm) + "\n")
    cmd = ["gcc", "-shared", "-nostdlib", "-o", base, base + ".s", f"-Wl,-soname,{so}"]
    if versions:
        with open(base + ".map", "w") as f:
            for ver, names in versions.items():
                f.write(f"{ver} {{ global: " + " ".join(f'"{n}";' for n in names) + " };\n")
            f.write("LOCALS { local: *; };\n")
        cmd.append(f"-Wl,--version-script={base}.map")
    subprocess.run(cmd, check=True)
    os.remove(base + ".s")
    if versions:
        os.remove(base + ".map")


if __name__ == "__main__":
    main()
