/* Rust's standard library on Windows draws random numbers from ProcessPrng in
 * bcryptprimitives.dll, which Debian 12's wine does not have. This stand-in, built with
 * mingw-w64 and put beside canctl.exe for the wine run in CI only, forwards to advapi32's
 * RtlGenRandom (SystemFunction036), which wine has. */
#include <windows.h>

typedef BOOLEAN(WINAPI *gen_random)(PVOID, ULONG);

BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T len) {
    static gen_random gen;
    if (!gen) {
        HMODULE advapi = LoadLibraryA("advapi32.dll");
        gen = advapi ? (gen_random)GetProcAddress(advapi, "SystemFunction036") : NULL;
        if (!gen) return FALSE;
    }
    while (len) {
        ULONG n = len > 0x40000000 ? 0x40000000 : (ULONG)len;
        if (!gen(data, n)) return FALSE;
        data += n;
        len -= n;
    }
    return TRUE;
}
