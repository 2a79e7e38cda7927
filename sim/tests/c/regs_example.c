/* A driver's use of rtl/regs/finequad_regs.h (PeakRDL-cheader): the register block as a
 * struct over memory, fields through the _bm/_bp macros. sim/tests/test_regs.py compiles
 * it with gcc -std=c99 -Wall -Wextra -Werror and runs it; it exits 0 if every check holds.
 * A fake register block in RAM stands in for the AXI4-Lite slave (no hardware here). */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "finequad_regs.h"

#define FIELD_SET(w, reg, f, v) \
    (((w) & ~FINEQUAD__##reg##__##f##_bm) | \
     (((uint32_t)(v) << FINEQUAD__##reg##__##f##_bp) & FINEQUAD__##reg##__##f##_bm))
#define FIELD_GET(w, reg, f) (((w) & FINEQUAD__##reg##__##f##_bm) >> FINEQUAD__##reg##__##f##_bp)

static int failures;

static void check(int ok, const char *what) {
    if (!ok) {
        printf("FAIL %s\n", what);
        failures++;
    }
}

int main(void) {
    static uint32_t ram[64];
    volatile finequad_t *fq = (volatile finequad_t *)(void *)ram;

    /* the map: ID at byte 0x7c, COUNT at 0x20, word 0 CTRL when written, STATUS when read */
    check(offsetof(finequad_t, ID) == 0x7c, "ID at 0x7c");
    check(offsetof(finequad_t, COUNT) == 0x20, "COUNT at 0x20");
    check(offsetof(finequad_t, CTRL_STATUS) == 0, "CTRL/STATUS at 0");
    check(sizeof(finequad_t) == 0x98, "the block is 38 words");

    /* a read-modify-write of a field leaves the register's other fields alone */
    fq->ABGEN = FINEQUAD__ABGEN__AB_SEP_reset << FINEQUAD__ABGEN__AB_SEP_bp;
    fq->ABGEN = FIELD_SET(fq->ABGEN, ABGEN, AB_SRC, 1);
    check(FIELD_GET(fq->ABGEN, ABGEN, AB_SEP) == FINEQUAD__ABGEN__AB_SEP_reset, "ab_sep kept");
    check(FIELD_GET(fq->ABGEN, ABGEN, AB_SRC) == 1, "ab_src set");
    check(ram[offsetof(finequad_t, ABGEN) / 4] == fq->ABGEN, "ABGEN is its word");

    /* a write of INTERP, and the CTRL pulses */
    fq->INTERP = FIELD_SET(0u, INTERP, INTERP, 200);
    check(ram[1] == 200, "INTERP is word 1");
    fq->CTRL_STATUS.CTRL = FIELD_SET(0u, CTRL, COV_RESET, 1);
    check(ram[0] == FINEQUAD__CTRL__COV_RESET_bm, "CTRL.cov_reset alone");

    /* decode a STATUS word and a fault word */
    ram[0] = FINEQUAD__STATUS__UNCAL_bm | FINEQUAD__STATUS__LOADED_bm;
    check(FIELD_GET(fq->CTRL_STATUS.STATUS, STATUS, UNCAL) == 1, "STATUS.uncal");
    check(FIELD_GET(fq->CTRL_STATUS.STATUS, STATUS, HOLD) == 0, "STATUS.hold");
    check(FIELD_GET(fq->CTRL_STATUS.STATUS, STATUS, LOADED) == 1, "STATUS.loaded");
    fq->FAULT_STICKY = FINEQUAD__FAULT_STICKY__CSAT_bm | FINEQUAD__FAULT_STICKY__GLITCH_bm;
    check(FIELD_GET(fq->FAULT_STICKY, FAULT_STICKY, CSAT) == 1, "fault csat");
    check(FIELD_GET(fq->FAULT_STICKY, FAULT_STICKY, STUCK) == 0, "fault stuck");

    /* a signed field: M1 reads sign-extended */
    ram[offsetof(finequad_t, M1) / 4] = 0xffff8000u;
    check((int32_t)fq->M1 == -32768, "M1 signed");

    /* the ID's reset value: "FQ" */
    check((FINEQUAD__ID__ID_reset >> 16) == 0x4651, "ID says FQ");

    printf("%d failure(s)\n", failures);
    return failures ? 1 : 0;
}
