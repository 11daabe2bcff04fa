/* startup.c - the vector table and the reset handler of a bare Cortex-M4F program (QEMU's MPS2
 * AN386 board): the FPU on (full access to CP10 and CP11 in CPACR) before any float instruction,
 * then newlib's _start (rdimon: semihosting for printf and exit).  examples/embed/m4/README.md. */
#include <stdint.h>

extern void _start(void);
extern uint32_t __stack_top__;
void reset_handler(void);
void fault_handler(void);

__attribute__((section(".vectors"), used)) static void (*const vectors[16])(void) = {
    (void (*)(void))(uintptr_t)&__stack_top__, reset_handler, fault_handler, fault_handler,
    fault_handler, fault_handler, fault_handler, 0, 0, 0, 0, fault_handler, fault_handler, 0, fault_handler,
    fault_handler};

void reset_handler(void)
{
    *(volatile uint32_t *)0xE000ED88u |= (0xFu << 20); /* SCB->CPACR: CP10, CP11 full access */
    __asm volatile("dsb\n\tisb");
    _start();
    for (;;) {
    }
}

void fault_handler(void)
{
    for (;;) {
    }
}
