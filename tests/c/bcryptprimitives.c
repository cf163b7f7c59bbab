/* bcryptprimitives.dll for wine 8 (Debian 12), which lacks it: Rust's std (1.78+) on Windows takes
 * its random seeds (HashMap keys) from ProcessPrng in this DLL, present on Windows 10 and later.
 * Placed beside the test harness only; the FMU's DLL imports the system one on real Windows.
 * Fills the buffer from RtlGenRandom (advapi32's SystemFunction036), as ProcessPrng always
 * succeeds. */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length) {
    while (length > 0) {
        ULONG n = length > 0x10000000 ? 0x10000000 : (ULONG)length;
        if (!SystemFunction036(data, n)) return FALSE;
        data += n;
        length -= n;
    }
    return TRUE;
}
