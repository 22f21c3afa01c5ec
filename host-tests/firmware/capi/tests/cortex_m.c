/* Start-up code and output for the C programs of the C API on Cortex-M under QEMU (mps2-an386,
 * Cortex-M4F; mps2-an385, Cortex-M3): vector table, reset handler (copy .data, zero .bss,
 * enable the FPU where there is one, run main), output to the host's stdout and exit through
 * ARM semihosting.
 * No C library: the Rust staticlib brings memcpy/memset (compiler-builtins), libgcc the rest.
 * Linked with cortex_m.ld. */
#include <stdint.h>
#include <stddef.h>

int main(void);
void vs_test_write(const char *s);
void vs_reset(void);
void vs_fault(void);

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;

/* One semihosting call: operation in r0, argument in r1, result in r0. */
static int semihost(int op, const void *arg) {
    register int r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

#define SYS_OPEN 0x01
#define SYS_WRITE 0x05
#define SYS_EXIT 0x18
/* SYS_EXIT reasons on 32-bit ARM (passed in r1 itself): QEMU exits with status 0 for
 * ApplicationExit and 1 for any other reason. */
#define ADP_STOPPED_APPLICATION_EXIT 0x20026
#define ADP_STOPPED_RUN_TIME_ERROR 0x20023

/* The host's stdout: SYS_OPEN of ":tt" for writing (mode 4), as cortex-m-semihosting does. */
static int out_handle = -1;

void vs_test_write(const char *s) {
    if (out_handle < 0) {
        const uint32_t open_args[3] = {(uint32_t)(uintptr_t)":tt", 4, 3};
        out_handle = semihost(SYS_OPEN, open_args);
    }
    size_t n = 0;
    while (s[n] != 0) n++;
    const uint32_t write_args[3] = {(uint32_t)out_handle, (uint32_t)(uintptr_t)s, (uint32_t)n};
    semihost(SYS_WRITE, write_args);
}

static void __attribute__((noreturn)) exit_with(int ok) {
    semihost(SYS_EXIT, (const void *)(uintptr_t)(ok ? ADP_STOPPED_APPLICATION_EXIT : ADP_STOPPED_RUN_TIME_ERROR));
    for (;;) {
    }
}

void vs_reset(void) {
    uint32_t *src = &_sidata, *dst = &_sdata;
    while (dst < &_edata) *dst++ = *src++;
    for (dst = &_sbss; dst < &_ebss;) *dst++ = 0;
#if defined(__ARM_FP)
    /* CPACR: full access to CP10 and CP11 (the FPU) before any float instruction. */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
#endif
    exit_with(main() == 0);
}

void vs_fault(void) {
    vs_test_write("fault\n");
    exit_with(0);
}

/* Initial stack pointer, reset, NMI, HardFault, MemManage, BusFault, UsageFault. */
__attribute__((section(".vectors"), used)) static void (*const vectors[7])(void) = {
    (void (*)(void))(uintptr_t)&_estack, vs_reset, vs_fault, vs_fault, vs_fault, vs_fault, vs_fault,
};
