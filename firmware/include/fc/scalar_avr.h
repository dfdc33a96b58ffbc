/*
 * fc/scalar_avr.h - the ATmega's port of the fixed backend. Included by
 * fc/scalar.h (fixed, __AVR__ only; nothing else includes it) before its
 * portable primitives; each FC_PORT_<NAME> defined here leaves that
 * portable definition out, and the one here takes its place, with the same
 * bits (platform/atmega/scalar_test checks every one against the portable
 * definition in simavr: atmega.scalar_equivalence).
 *
 * Why a port at all: avr-gcc 5.4 computes (int64_t)a * b by __mulsidi3 and
 * shifts, adds and compares int64_t through libgcc loops; a 32-bit shift by
 * a constant that is not a multiple of 8 is a loop at -Os. So here the
 * 64-bit intermediate of a product is never a C int64_t: it is the pair of
 * 32-bit halves of fc_fx_wide, and the steps that need more than 32-bit C
 * are written out in AVR assembly.
 *
 *   replaced            (macro)            how, and why
 *   fc_add, fc_sub,     FC_PORT_ADD        ADD/ADC and the V flag (avr-gcc
 *   fc_add_inline,                         compares the sum twice); fc_add
 *   fc_sub_inline                          and fc_sub one copy each, called
 *                                          (scalar.c): inlined at every site
 *                                          they overflow the flash; the
 *                                          _inline forms for the sites that
 *                                          run at every step
 *   fc_mul, fc_dot2,    FC_PORT_PRODUCTS   one out-of-line copy each (scalar.c,
 *   fc_dot3, fc_dot4,                      the shift at run time): inlined at
 *   fc_mul_inline,                         every site they overflow the flash;
 *   fc_dot2_inline                         the _inline forms on the halves,
 *                                          inline, for the hottest sites
 *   fc_acc_mac          FC_PORT_ACC_MAC    out of line (scalar.c)
 *   fc_narrow16         FC_PORT_NARROW16   a shift of 16: the high half
 *   fc_mul16,           FC_PORT_MUL16      MULS/MULSU/MUL (avr-gcc calls libgcc)
 *   fc_mul16_unsigned,
 *   fc_umul16
 *   fc_sq16             FC_PORT_SQ16       one MULSU for the cross product
 *   fc_mul_gain         FC_PORT_MUL_GAIN   assembly, out of line (scalar.c)
 *   fc_fx_mul_wide,     FC_PORT_HALVES     the helpers under fc_fx_narrow,
 *   fc_fx_umul_wide,                       fc_convert, fc_mul_by16 and
 *   fc_fx_extract,                         scalar.c's roots: MUL by bytes,
 *   fc_fx_asr32,                           constant shifts by bytes and bits;
 *   fc_fx_shl32,                           fc_convert's last bit by the carry
 *   fc_fx_halve_rounded
 *   fc_fx_low16_asr     FC_PORT_LOW16_ASR  fc_round16's shift: the two bytes
 *                                          kept, by LSL/ROL
 *   fc_sqrt_unit16      FC_PORT_SQRT_UNIT16  inline: a knot table's chord and
 *                                          exact steps in assembly (the
 *                                          allocation's rotor speeds)
 *
 * The assembly below:
 *   fc_avr_mul_u32   32 x 32 -> 64 unsigned: the 16 byte products of the
 *                    schoolbook method (MUL, 2 cycles each), summed by
 *                    output byte (no call)
 *   FC_AVR_ASR64     arithmetic shift right of the 8 bytes by 0..7 bits
 *                    (ASR/ROR, 8 cycles a bit), the part of a shift that is
 *                    not a whole number of bytes
 *
 * The signed product follows from the unsigned one of the same bit patterns
 * (two's complement, modulo 2^64):
 *   a b = A B - 2^32 (a < 0 ? B : 0) - 2^32 (b < 0 ? A : 0)
 * with A, B the operands read as unsigned, so only the high half is corrected.
 */
#ifndef FC_SCALAR_AVR_H
#define FC_SCALAR_AVR_H

#if !defined(__AVR__)
#error "fc/scalar_avr.h is for avr-gcc only (fc/scalar.h includes it)"
#endif

#include <avr/pgmspace.h>
#include <stdint.h>

/* *low + 2^32 *high = a b, unsigned, by product scanning: the 16 byte
 * products a_i b_j taken by output byte k = i + j, each added into the three
 * bytes k..k+2 of the result, which hold the sum of the bytes below k's
 * columns' carries. No carry leaves byte k + 2: the products of the columns
 * up to k sum to less than 4 2^16 2^(8k) + 2^(8k+16) < 2^(8k+19). Byte k + 3
 * is cleared before column k + 1 reaches it. 3 cycles of adds a product, 86
 * in all (against 102 for the diagonal first and each product's carry
 * carried to the top). r0:r1 take each MUL's product; r1 is avr-gcc's zero
 * register and is cleared again at the end. */
static inline __attribute__((always_inline)) void fc_avr_mul_u32(uint32_t a, uint32_t b, uint32_t *low,
                                                                  uint32_t *high)
{
    uint32_t lo, hi;
    uint8_t zero;
    __asm__("clr %2\n\t"
            "clr %C0\n\t"
            /* byte 0: a0 b0 */
            "mul %A3, %A4\n\t" "mov %A0, r0\n\t" "mov %B0, r1\n\t"
            "clr %D0\n\t"
            /* byte 1: a0 b1, a1 b0 */
            "mul %A3, %B4\n\t" "add %B0, r0\n\t" "adc %C0, r1\n\t" "adc %D0, %2\n\t"
            "mul %B3, %A4\n\t" "add %B0, r0\n\t" "adc %C0, r1\n\t" "adc %D0, %2\n\t"
            "clr %A1\n\t"
            /* byte 2: a0 b2, a1 b1, a2 b0 */
            "mul %A3, %C4\n\t" "add %C0, r0\n\t" "adc %D0, r1\n\t" "adc %A1, %2\n\t"
            "mul %B3, %B4\n\t" "add %C0, r0\n\t" "adc %D0, r1\n\t" "adc %A1, %2\n\t"
            "mul %C3, %A4\n\t" "add %C0, r0\n\t" "adc %D0, r1\n\t" "adc %A1, %2\n\t"
            "clr %B1\n\t"
            /* byte 3: a0 b3, a1 b2, a2 b1, a3 b0 */
            "mul %A3, %D4\n\t" "add %D0, r0\n\t" "adc %A1, r1\n\t" "adc %B1, %2\n\t"
            "mul %B3, %C4\n\t" "add %D0, r0\n\t" "adc %A1, r1\n\t" "adc %B1, %2\n\t"
            "mul %C3, %B4\n\t" "add %D0, r0\n\t" "adc %A1, r1\n\t" "adc %B1, %2\n\t"
            "mul %D3, %A4\n\t" "add %D0, r0\n\t" "adc %A1, r1\n\t" "adc %B1, %2\n\t"
            "clr %C1\n\t"
            /* byte 4: a1 b3, a2 b2, a3 b1 */
            "mul %B3, %D4\n\t" "add %A1, r0\n\t" "adc %B1, r1\n\t" "adc %C1, %2\n\t"
            "mul %C3, %C4\n\t" "add %A1, r0\n\t" "adc %B1, r1\n\t" "adc %C1, %2\n\t"
            "mul %D3, %B4\n\t" "add %A1, r0\n\t" "adc %B1, r1\n\t" "adc %C1, %2\n\t"
            "clr %D1\n\t"
            /* byte 5: a2 b3, a3 b2 */
            "mul %C3, %D4\n\t" "add %B1, r0\n\t" "adc %C1, r1\n\t" "adc %D1, %2\n\t"
            "mul %D3, %C4\n\t" "add %B1, r0\n\t" "adc %C1, r1\n\t" "adc %D1, %2\n\t"
            /* byte 6: a3 b3 */
            "mul %D3, %D4\n\t" "add %C1, r0\n\t" "adc %D1, r1\n\t"
            "clr __zero_reg__"
            : "=&r"(lo), "=&r"(hi), "=&r"(zero)
            : "r"(a), "r"(b));
    *low = lo;
    *high = hi;
}

/* one bit of the arithmetic shift right of %1:%0 (high:low) */
#define FC_AVR_ASR1                                                                            \
    "asr %D1\n\tror %C1\n\tror %B1\n\tror %A1\n\tror %D0\n\tror %C0\n\tror %B0\n\tror %A0\n\t"

/* high:low >> BITS, arithmetic, BITS in 0..7. A compile-time BITS is
 * unrolled (8 cycles a bit); a run-time one (a shift passed down to a
 * function that is not inlined) is a counted loop. A macro: the "n"
 * constraint needs the constant itself, not a parameter. */
#define FC_AVR_ASR64(low, high, BITS)                                                           \
    do {                                                                                      \
        if (__builtin_constant_p(BITS)) {                                                     \
            /* written out, not .rept: gcc sizes its branches by the asm's lines */            \
            switch ((BITS) & 7) {                                                             \
            case 1: __asm__(FC_AVR_ASR1 : "+r"(low), "+r"(high)); break;                      \
            case 2: __asm__(FC_AVR_ASR1 FC_AVR_ASR1 : "+r"(low), "+r"(high)); break;          \
            case 3: __asm__(FC_AVR_ASR1 FC_AVR_ASR1 FC_AVR_ASR1 : "+r"(low), "+r"(high)); break; \
            case 4: __asm__(FC_AVR_ASR1 FC_AVR_ASR1 FC_AVR_ASR1 FC_AVR_ASR1                   \
                            : "+r"(low), "+r"(high)); break;                                  \
            case 5: __asm__(FC_AVR_ASR1 FC_AVR_ASR1 FC_AVR_ASR1 FC_AVR_ASR1 FC_AVR_ASR1       \
                            : "+r"(low), "+r"(high)); break;                                  \
            case 6: __asm__(FC_AVR_ASR1 FC_AVR_ASR1 FC_AVR_ASR1 FC_AVR_ASR1 FC_AVR_ASR1       \
                            FC_AVR_ASR1 : "+r"(low), "+r"(high)); break;                      \
            case 7: __asm__(FC_AVR_ASR1 FC_AVR_ASR1 FC_AVR_ASR1 FC_AVR_ASR1 FC_AVR_ASR1       \
                            FC_AVR_ASR1 FC_AVR_ASR1 : "+r"(low), "+r"(high)); break;          \
            default: break;                                                                   \
            }                                                                                 \
        } else {                                                                              \
            uint8_t fc_avr_count = (uint8_t)((BITS) & 7);                                     \
            if (fc_avr_count != 0u) {                                                         \
                __asm__(".Lfc_asr64_%=:\n\t"                                                  \
                        "asr %D1\n\tror %C1\n\tror %B1\n\tror %A1\n\t"                        \
                        "ror %D0\n\tror %C0\n\tror %B0\n\tror %A0\n\t"                        \
                        "dec %2\n\t"                                                          \
                        "brne .Lfc_asr64_%="                                                  \
                        : "+r"(low), "+r"(high), "+r"(fc_avr_count));                         \
            }                                                                                 \
        }                                                                                     \
    } while (0)

/* The five bytes top:word shifted right by BITS (1..4, a constant), the low
 * four kept in word: LSR/ROR, 5 cycles a bit. */
#define FC_AVR_SHR40_1 "lsr %1\n\tror %D0\n\tror %C0\n\tror %B0\n\tror %A0\n\t"
#define FC_AVR_SHR40(word, top, BITS)                                                          \
    do {                                                                                      \
        switch (BITS) {                                                                       \
        case 1: __asm__(FC_AVR_SHR40_1 : "+r"(word), "+r"(top)); break;                       \
        case 2: __asm__(FC_AVR_SHR40_1 FC_AVR_SHR40_1 : "+r"(word), "+r"(top)); break;        \
        case 3: __asm__(FC_AVR_SHR40_1 FC_AVR_SHR40_1 FC_AVR_SHR40_1                          \
                        : "+r"(word), "+r"(top)); break;                                      \
        case 4: __asm__(FC_AVR_SHR40_1 FC_AVR_SHR40_1 FC_AVR_SHR40_1 FC_AVR_SHR40_1           \
                        : "+r"(word), "+r"(top)); break;                                      \
        default: break;                                                                       \
        }                                                                                     \
    } while (0)

/* The five bytes word:bottom shifted left by BITS (1..3, a constant), the high
 * four kept in word: LSL/ROL, 5 cycles a bit. */
#define FC_AVR_SHL40_1 "lsl %1\n\trol %A0\n\trol %B0\n\trol %C0\n\trol %D0\n\t"
#define FC_AVR_SHL40(word, bottom, BITS)                                                       \
    do {                                                                                      \
        switch (BITS) {                                                                       \
        case 1: __asm__(FC_AVR_SHL40_1 : "+r"(word), "+r"(bottom)); break;                    \
        case 2: __asm__(FC_AVR_SHL40_1 FC_AVR_SHL40_1 : "+r"(word), "+r"(bottom)); break;     \
        case 3: __asm__(FC_AVR_SHL40_1 FC_AVR_SHL40_1 FC_AVR_SHL40_1                          \
                        : "+r"(word), "+r"(bottom)); break;                                   \
        default: break;                                                                       \
        }                                                                                     \
    } while (0)

/*
 * ROUNDS rounds of restoring division (the divisions and square roots of
 * scalar.c): each round shifts rem:low left by one bit and, when rem >= d,
 * subtracts d and sets the bit that came free at the bottom of low, so after
 * ROUNDS rounds the low ROUNDS bits of low are the quotient bits and rem the
 * remainder. Needs rem < d <= 2^31 on entry (then 2 rem + 1 < 2^32: no bit
 * leaves rem). About 21 cycles a round, against some 40 for the same C.
 */
static inline __attribute__((always_inline)) void fc_avr_divide_rounds(uint32_t *rem, uint32_t *low, uint32_t d,
                                                                        uint8_t rounds)
{
    uint32_t r = *rem, l = *low;
    __asm__("1:\n\t"
            "lsl %A1\n\trol %B1\n\trol %C1\n\trol %D1\n\t"
            "rol %A0\n\trol %B0\n\trol %C0\n\trol %D0\n\t"
            "cp %A0, %A3\n\tcpc %B0, %B3\n\tcpc %C0, %C3\n\tcpc %D0, %D3\n\t"
            "brlo 2f\n\t"
            "sub %A0, %A3\n\tsbc %B0, %B3\n\tsbc %C0, %C3\n\tsbc %D0, %D3\n\t"
            "inc %A1\n\t" /* bit 0 of low is 0 after the shift */
            "2:\n\t"
            "dec %2\n\t"
            "brne 1b"
            : "+r"(r), "+r"(l), "+r"(rounds)
            : "r"(d));
    *rem = r;
    *low = l;
}


/* One round of restoring division in fc_div: rem r27:r24, low r23:r20,
 * d r31:r30:r19:r18 (as fc_avr_divide_rounds) */
#define FC_AVR_DIV_ROUND                                                                       \
    "lsl r20\n\trol r21\n\trol r22\n\trol r23\n\t"                                            \
    "rol r24\n\trol r25\n\trol r26\n\trol r27\n\t"                                            \
    "cp r24, r18\n\tcpc r25, r19\n\tcpc r26, r30\n\tcpc r27, r31\n\t"                         \
    "brlo 11f\n\t"                                                                            \
    "sub r24, r18\n\tsbc r25, r19\n\tsbc r26, r30\n\tsbc r27, r31\n\t"                        \
    "inc r20\n"                                                                               \
    "11:\n\t"

/*
 * fc_div on the ATmega, round(num 2^shift / den) saturated at +-INT32_MAX as
 * the int64_t form: one out-of-line function in assembly (scalar.c, naked)
 * with the registers of the calling convention and r16 (saved):
 *   in   ar r25:r24, num r23-r20, den r19-r16, shift r15:r14 (read only)
 *   out  r25-r22
 * den == 0 and shifts outside 0..31 go to the portable definition
 * (fc_fx_div_portable, a tail call). Otherwise
 * ar waits in r0:r1 (r1 cleared before the return), the sign of the
 * quotient in the T flag; magnitudes d = |den| in r31:r30:r19:r18,
 * N = |num| 2^shift in rem:low = r27-r24:r23-r20, then restoring division:
 *   rem:low = N                       (whole bytes by moves, then bits)
 *   rem >= d                          N / d >= 2^32: saturated
 *   rem:low shifted by whole bytes    while the byte shifted in keeps
 *                                     rem < d (those 8 rounds set no bit)
 *   8 rounds a byte for the rest      (unrolled; each as
 *                                     fc_avr_divide_rounds)
 * so low and rem are the quotient q and remainder r of the rounds over all
 * 32 bits (rem < d <= 2^31: no bit leaves rem). Rounding from r:
 *   floor((q d + r + floor(d/2)) / d) = q + (r >= d - floor(d/2)) = q + (2 r >= d)
 * saturated when q or q + 1 has bit 31 set (q >= 2^31 is caught before the
 * increment, which then cannot wrap). The same value and saturation as the
 * int64_t form (atmega.scalar_equivalence).
 */
#define FC_AVR_DIV_BODY                                                                        \
    "cp r16, __zero_reg__\n\tcpc r17, __zero_reg__\n\t"                                        \
    "cpc r18, __zero_reg__\n\tcpc r19, __zero_reg__\n\t"                                       \
    "brne 30f\n\t"                                                                             \
    "jmp fc_fx_div_portable\n"                                                                 \
    "30:\n\t"                                                                                  \
    "tst r15\n\t"                                                                              \
    "breq 31f\n\t"                                                                             \
    "jmp fc_fx_div_portable\n"                                                                 \
    "31:\n\t"                                                                                  \
    "mov r30, r14\n\t"                                                                         \
    "cpi r30, 32\n\t"                                                                          \
    "brlo 32f\n\t"                                                                             \
    "jmp fc_fx_div_portable\n"                                                                 \
    "32:\n\t"                                                                                  \
    "push r16\n\t"                                                                             \
    "movw r0, r24\n\t"                                                                         \
    /* d = |den|, T = the sign of num den */                                                   \
    "mov r30, r18\n\tmov r31, r19\n\tmovw r18, r16\n\t"                                        \
    "mov r16, r23\n\teor r16, r31\n\tbst r16, 7\n\t"                                           \
    "sbrs r31, 7\n\t"                                                                          \
    "rjmp 1f\n\t"                                                                              \
    "com r31\n\tcom r30\n\tcom r19\n\tneg r18\n\t"                                             \
    "sbci r19, 0xFF\n\tsbci r30, 0xFF\n\tsbci r31, 0xFF\n"                                     \
    "1:\n\t"                                                                                   \
    "sbrs r23, 7\n\t"                                                                          \
    "rjmp 2f\n\t"                                                                              \
    "com r23\n\tcom r22\n\tcom r21\n\tneg r20\n\t"                                             \
    "sbci r21, 0xFF\n\tsbci r22, 0xFF\n\tsbci r23, 0xFF\n"                                     \
    /* rem:low = |num| 2^shift: whole bytes, then the bits */                                  \
    "2:\n\t"                                                                                   \
    "clr r24\n\tclr r25\n\tmovw r26, r24\n\t"                                                  \
    "mov r16, r14\n\t"                                                                         \
    "cpi r16, 8\n\t"                                                                           \
    "brlo 4f\n"                                                                                \
    "3:\n\t"                                                                                   \
    "mov r27, r26\n\tmov r26, r25\n\tmov r25, r24\n\tmov r24, r23\n\t"                         \
    "mov r23, r22\n\tmov r22, r21\n\tmov r21, r20\n\tclr r20\n\t"                              \
    "subi r16, 8\n\t"                                                                          \
    "cpi r16, 8\n\t"                                                                           \
    "brsh 3b\n"                                                                                \
    "4:\n\t"                                                                                   \
    "tst r16\n\t"                                                                              \
    "breq 6f\n"                                                                                \
    "5:\n\t"                                                                                   \
    "lsl r20\n\trol r21\n\trol r22\n\trol r23\n\t"                                             \
    "rol r24\n\trol r25\n\trol r26\n\trol r27\n\t"                                             \
    "dec r16\n\t"                                                                              \
    "brne 5b\n"                                                                                \
    /* the quotient reaches 2^32: saturated */                                                 \
    "6:\n\t"                                                                                   \
    "cp r24, r18\n\tcpc r25, r19\n\tcpc r26, r30\n\tcpc r27, r31\n\t"                          \
    "brlo 7f\n\t"                                                                              \
    "rjmp 20f\n"                                                                               \
    /* whole bytes while the next one leaves rem below d */                                    \
    "7:\n\t"                                                                                   \
    "ldi r16, 4\n"                                                                             \
    "8:\n\t"                                                                                   \
    "tst r27\n\t"                                                                              \
    "brne 10f\n\t"                                                                             \
    "cp r23, r18\n\tcpc r24, r19\n\tcpc r25, r30\n\tcpc r26, r31\n\t"                          \
    "brsh 10f\n\t"                                                                             \
    "mov r27, r26\n\tmov r26, r25\n\tmov r25, r24\n\tmov r24, r23\n\t"                         \
    "mov r23, r22\n\tmov r22, r21\n\tmov r21, r20\n\tclr r20\n\t"                              \
    "dec r16\n\t"                                                                              \
    "brne 8b\n\t"                                                                              \
    "rjmp 12f\n"                                                                               \
    /* 8 rounds for each byte left */                                                          \
    "10:\n\t"                                                                                  \
    FC_AVR_DIV_ROUND FC_AVR_DIV_ROUND FC_AVR_DIV_ROUND FC_AVR_DIV_ROUND                     \
    FC_AVR_DIV_ROUND FC_AVR_DIV_ROUND FC_AVR_DIV_ROUND FC_AVR_DIV_ROUND                     \
    "dec r16\n\t"                                                                              \
    "breq 12f\n\t"                                                                             \
    "rjmp 10b\n"                                                                               \
    /* round: q + 1 when 2 rem >= d; q or q + 1 >= 2^31 saturated */                           \
    "12:\n\t"                                                                                  \
    "sbrc r23, 7\n\t"                                                                          \
    "rjmp 20f\n\t"                                                                             \
    "lsl r24\n\trol r25\n\trol r26\n\trol r27\n\t"                                             \
    "cp r24, r18\n\tcpc r25, r19\n\tcpc r26, r30\n\tcpc r27, r31\n\t"                          \
    "brlo 13f\n\t"                                                                             \
    "subi r20, 0xFF\n\tsbci r21, 0xFF\n\tsbci r22, 0xFF\n\tsbci r23, 0xFF\n\t"                 \
    "sbrc r23, 7\n\t"                                                                          \
    "rjmp 20f\n"                                                                               \
    /* the signed result */                                                                    \
    "13:\n\t"                                                                                  \
    "movw r24, r22\n\tmovw r22, r20\n\t"                                                       \
    "brtc 14f\n\t"                                                                             \
    "com r25\n\tcom r24\n\tcom r23\n\tneg r22\n\t"                                             \
    "sbci r23, 0xFF\n\tsbci r24, 0xFF\n\tsbci r25, 0xFF\n"                                     \
    "14:\n\t"                                                                                  \
    "pop r16\n\t"                                                                              \
    "clr r1\n\t"                                                                               \
    "ret\n"                                                                                    \
    /* saturated: ar->saturated = 1, +-INT32_MAX by the sign */                                \
    "20:\n\t"                                                                                  \
    "movw r30, r0\n\t"                                                                         \
    "ldi r16, 1\n\t"                                                                           \
    "st Z, r16\n\t"                                                                            \
    "ldi r22, 0xFF\n\tldi r23, 0xFF\n\tldi r24, 0xFF\n\tldi r25, 0x7F\n\t"                     \
    "brtc 14b\n\t"                                                                             \
    "ldi r22, 0x01\n\tldi r23, 0\n\tldi r24, 0\n\tldi r25, 0x80\n\t"                           \
    "rjmp 14b"

/* scalar.c: fc_div is the assembly above; the portable definition */
fc_real fc_fx_div_portable(fc_arith *ar, fc_real num, fc_real den, int shift);

/*
 * round(sqrt(m)) 2^14 for m = 4 x, 0 < x <= 2^30 - 2^14 (fc_sqrt_unit16: x
 * in UNIT's Q30, m in Q32, the result the root in Q30; above that range the
 * rounded root is 2^16, which the caller returns itself). The rounded root
 * R is the integer with R^2 - R < m <= R^2 + R, found from a first guess by
 * steps:
 *   M = m 4^k in [2^30, 2^32)        (whole bytes by moves, then pairs of bits)
 *   S0 = 2^15 + T[i] + floor(d c / 2^8) + 1, at most 2^16 - 1
 *                                    (i = M's top byte, 64..255, c the next
 *                                    one; T[i] = round(2^16 sqrt(i / 2^8)) - 2^15,
 *                                    table[i - 64], and d = T[i+1] - T[i] < 2^8:
 *                                    the chord of the root over M's top 16 bits)
 *   R0 = floor(S0 / 2^k)             (sqrt(m) = sqrt(M) / 2^k)
 *   R  = R0 stepped up while m > R^2 + R, then down while m <= R^2 - R
 *                                    (R^2 + R and R^2 - R kept by adds: one product)
 * Exact whatever the guess: the table only bounds the steps (over every m:
 * at most two up or one down). table points to the 193
 * entries in program memory, the low 64 KB (LPM).
 */
static inline __attribute__((always_inline)) uint32_t fc_avr_sqrt_chord_q14(uint32_t x, const uint16_t *table)
{
    uint32_t m = x;
    uint32_t big;  /* M, then R^2 + R, R^2 - R, then the result */
    uint16_t root; /* S0, R0, R */
    uint8_t k;
    const uint16_t *z = table;
    __asm__("lsl %A[m]\n\trol %B[m]\n\trol %C[m]\n\trol %D[m]\n\t"
            "lsl %A[m]\n\trol %B[m]\n\trol %C[m]\n\trol %D[m]\n\t"
            "movw %A[big], %A[m]\n\t"
            "movw %C[big], %C[m]\n\t"
            "clr %[k]\n"
            /* M = m 4^k: whole bytes while the top one is 0 (m >= 4 ends it) */
            "1:\n\t"
            "tst %D[big]\n\t"
            "brne 2f\n\t"
            "mov %D[big], %C[big]\n\t"
            "mov %C[big], %B[big]\n\t"
            "mov %B[big], %A[big]\n\t"
            "clr %A[big]\n\t"
            "inc %[k]\n\tinc %[k]\n\tinc %[k]\n\tinc %[k]\n\t"
            "rjmp 1b\n"
            /* then pairs of bits while M < 2^30 */
            "2:\n\t"
            "sbrc %D[big], 7\n\t"
            "rjmp 3f\n\t"
            "sbrc %D[big], 6\n\t"
            "rjmp 3f\n\t"
            "lsl %A[big]\n\trol %B[big]\n\trol %C[big]\n\trol %D[big]\n\t"
            "lsl %A[big]\n\trol %B[big]\n\trol %C[big]\n\trol %D[big]\n\t"
            "inc %[k]\n\t"
            "rjmp 2b\n"
            /* the knot T[i] at table + 2 (i - 64), and d from the next one's
             * low byte (d < 2^8) */
            "3:\n\t"
            "subi r30, lo8(128)\n\t"
            "sbci r31, hi8(128)\n\t"
            "add r30, %D[big]\n\t"
            "adc r31, __zero_reg__\n\t"
            "add r30, %D[big]\n\t"
            "adc r31, __zero_reg__\n\t"
            "lpm %A[root], Z+\n\t"
            "lpm %B[root], Z+\n\t"
            "lpm r0, Z\n\t"
            "sub r0, %A[root]\n\t"
            "mul r0, %C[big]\n\t"
            "add %A[root], r1\n\t"
            "brcc 4f\n\t"
            "inc %B[root]\n"
            "4:\n\t"
            /* + 2^15 + 1; a carry out (only at M = 2^32 - 2^16) keeps 2^16 - 1 */
            "subi %A[root], lo8(-32769)\n\t"
            "sbci %B[root], hi8(-32769)\n\t"
            "brcs 11f\n\t"
            "ldi %A[root], 0xff\n\t"
            "ldi %B[root], 0xff\n"
            /* R0 = S0 / 2^k; k is 0 after it (the zero of what follows) */
            "11:\n\t"
            "tst %[k]\n\t"
            "breq 6f\n"
            "5:\n\t"
            "lsr %B[root]\n\t"
            "ror %A[root]\n\t"
            "dec %[k]\n\t"
            "brne 5b\n"
            /* R^2 + R */
            "6:\n\t"
            "mul %A[root], %A[root]\n\t"
            "movw %A[big], r0\n\t"
            "mul %B[root], %B[root]\n\t"
            "movw %C[big], r0\n\t"
            "mul %A[root], %B[root]\n\t"
            "add %B[big], r0\n\tadc %C[big], r1\n\tadc %D[big], %[k]\n\t"
            "add %B[big], r0\n\tadc %C[big], r1\n\tadc %D[big], %[k]\n\t"
            "add %A[big], %A[root]\n\tadc %B[big], %B[root]\n\tadc %C[big], %[k]\n\tadc %D[big], %[k]\n"
            /* up while m > R^2 + R: R + 1, and (R + 1)^2 + (R + 1) = R^2 + R + 2 (R + 1) */
            "7:\n\t"
            "cp %A[big], %A[m]\n\tcpc %B[big], %B[m]\n\tcpc %C[big], %C[m]\n\tcpc %D[big], %D[m]\n\t"
            "brsh 8f\n\t"
            "subi %A[root], 0xff\n\t"
            "sbci %B[root], 0xff\n\t"
            "add %A[big], %A[root]\n\tadc %B[big], %B[root]\n\tadc %C[big], %[k]\n\tadc %D[big], %[k]\n\t"
            "add %A[big], %A[root]\n\tadc %B[big], %B[root]\n\tadc %C[big], %[k]\n\tadc %D[big], %[k]\n\t"
            "rjmp 7b\n"
            /* R^2 - R = (R^2 + R) - 2 R */
            "8:\n\t"
            "sub %A[big], %A[root]\n\tsbc %B[big], %B[root]\n\tsbc %C[big], %[k]\n\tsbc %D[big], %[k]\n\t"
            "sub %A[big], %A[root]\n\tsbc %B[big], %B[root]\n\tsbc %C[big], %[k]\n\tsbc %D[big], %[k]\n"
            /* down while m <= R^2 - R: R - 1, and (R - 1)^2 - (R - 1) = R^2 - R - 2 (R - 1) */
            "9:\n\t"
            "cp %A[big], %A[m]\n\tcpc %B[big], %B[m]\n\tcpc %C[big], %C[m]\n\tcpc %D[big], %D[m]\n\t"
            "brlo 10f\n\t"
            "subi %A[root], 1\n\t"
            "sbci %B[root], 0\n\t"
            "sub %A[big], %A[root]\n\tsbc %B[big], %B[root]\n\tsbc %C[big], %[k]\n\tsbc %D[big], %[k]\n\t"
            "sub %A[big], %A[root]\n\tsbc %B[big], %B[root]\n\tsbc %C[big], %[k]\n\tsbc %D[big], %[k]\n\t"
            "rjmp 9b\n"
            /* R 2^14: R 2^16 by moves, two bits back */
            "10:\n\t"
            "clr %A[big]\n\t"
            "clr %B[big]\n\t"
            "movw %C[big], %A[root]\n\t"
            "lsr %D[big]\n\tror %C[big]\n\tror %B[big]\n\t"
            "lsr %D[big]\n\tror %C[big]\n\tror %B[big]\n\t"
            "clr __zero_reg__"
            : [big] "=&r"(big), [root] "=&d"(root), [k] "=&r"(k), [m] "+r"(m), "+z"(z));
    return big;
}

/* fc_sqrt_unit16 (FC_PORT_SQRT_UNIT16): inline, at the allocation's one
 * site (a call and the saves its asm's registers need cost more than the
 * tests around it), the root from fc_avr_sqrt_chord_q14 with its knots in
 * program memory: round(2^16 sqrt(i / 2^8)) - 2^15 for i = 64..256, 0 to
 * 2^15. The same bits as the portable definition (scalar.c), over every x. */
#define FC_PORT_SQRT_UNIT16
FC_FX_INLINE fc_real fc_sqrt_unit16(fc_arith *ar, fc_real x_unit)
{
    static const uint16_t knots[193] PROGMEM = {
        0, 255, 508, 759, 1008, 1256, 1502, 1746, 1988, 2228, 2467, 2704,
        2940, 3174, 3407, 3638, 3868, 4096, 4323, 4548, 4772, 4995, 5217, 5437,
        5656, 5874, 6090, 6305, 6519, 6732, 6944, 7155, 7364, 7573, 7780, 7987,
        8192, 8396, 8600, 8802, 9003, 9204, 9403, 9601, 9799, 9995, 10191, 10386,
        10580, 10773, 10965, 11157, 11347, 11537, 11726, 11914, 12101, 12288, 12474, 12659,
        12843, 13027, 13209, 13392, 13573, 13754, 13934, 14113, 14291, 14469, 14647, 14823,
        14999, 15174, 15349, 15523, 15697, 15869, 16041, 16213, 16384, 16554, 16724, 16893,
        17062, 17230, 17398, 17564, 17731, 17897, 18062, 18227, 18391, 18555, 18718, 18881,
        19043, 19204, 19366, 19526, 19686, 19846, 20005, 20164, 20322, 20480, 20637, 20794,
        20951, 21106, 21262, 21417, 21572, 21726, 21879, 22033, 22186, 22338, 22490, 22642,
        22793, 22944, 23094, 23244, 23394, 23543, 23691, 23840, 23988, 24135, 24283, 24430,
        24576, 24722, 24868, 25013, 25158, 25303, 25447, 25591, 25735, 25878, 26021, 26163,
        26305, 26447, 26589, 26730, 26871, 27011, 27151, 27291, 27431, 27570, 27709, 27847,
        27985, 28123, 28261, 28398, 28535, 28672, 28808, 28944, 29080, 29216, 29351, 29486,
        29620, 29755, 29889, 30022, 30156, 30289, 30422, 30555, 30687, 30819, 30951, 31082,
        31214, 31345, 31475, 31606, 31736, 31866, 31995, 32125, 32254, 32383, 32511, 32640,
        32768
    };
    (void)ar;
    if (x_unit <= 0) {
        return 0;
    }
    /* x above 1 - 2^-16 (m = 4 x > 65535^2 + 65535): the root rounds to 2^16, 1 in UNIT */
    if (x_unit > FC_INT(1, UNIT) - (fc_real)((uint32_t)1u << (FC_UNIT_FRAC - 16))) {
        return FC_INT(1, UNIT);
    }
    return (fc_real)fc_avr_sqrt_chord_q14((uint32_t)x_unit, knots);
}

/* Byte i (0..7) and the 32-bit word at byte i (0..4) of high:low, i a constant:
 * C shifts by whole bytes, which avr-gcc does by moves. */
static inline __attribute__((always_inline)) uint8_t fc_avr_byte(uint32_t low, uint32_t high, int i)
{
    return (uint8_t)(i < 4 ? low >> (8 * (i & 3)) : high >> (8 * (i & 3)));
}

static inline __attribute__((always_inline)) uint32_t fc_avr_word(uint32_t low, uint32_t high, int i)
{
    if (i <= 0 || i >= 4) {
        return i <= 0 ? low : high;
    }
    /* byte by byte (the shifts and OR of the C form cost moves and ORs) */
    union {
        uint32_t word;
        uint8_t bytes[4];
    } w;
    w.bytes[0] = fc_avr_byte(low, high, i);
    w.bytes[1] = fc_avr_byte(low, high, i + 1);
    w.bytes[2] = fc_avr_byte(low, high, i + 2);
    w.bytes[3] = fc_avr_byte(low, high, i + 3);
    return w.word;
}

/* ======================================================================= */
/* the halves (FC_PORT_HALVES)                                             */
/* ======================================================================= */
#define FC_PORT_HALVES

/* fc_fx_mul_wide: the unsigned product of the bit patterns, then the high
 * half corrected for the signs (above); fc_fx_umul_wide: the product itself */
FC_FX_INLINE fc_fx_wide fc_fx_mul_wide(int32_t a, int32_t b)
{
    fc_fx_wide product;
    fc_avr_mul_u32((uint32_t)a, (uint32_t)b, &product.low, &product.high);
    if (a < 0) {
        product.high -= (uint32_t)b;
    }
    if (b < 0) {
        product.high -= (uint32_t)a;
    }
    return product;
}

FC_FX_INLINE fc_fx_wide fc_fx_umul_wide(uint32_t a, uint32_t b)
{
    fc_fx_wide product;
    fc_avr_mul_u32(a, b, &product.low, &product.high);
    return product;
}

/* fc_fx_extract: a C shift by a constant that is not a multiple of 8 is a
 * loop at -Os, so whole bytes by moves, then the 0..7 bits left of 40 bits,
 * the shorter way; a run-time shift by bytes, then an ASR/ROR loop */
FC_FX_INLINE uint32_t fc_fx_extract(uint32_t low, uint32_t high, int shift)
{
    if (__builtin_constant_p(shift)) {
        const int bytes = shift / 8, bits = shift % 8;
        if (bits <= 4) {
            uint32_t word = fc_avr_word(low, high, bytes);
            uint8_t top = fc_avr_byte(low, high, bytes + 4);
            FC_AVR_SHR40(word, top, bits);
            return word;
        }
        uint32_t word = fc_avr_word(low, high, bytes + 1);
        uint8_t bottom = fc_avr_byte(low, high, bytes);
        FC_AVR_SHL40(word, bottom, 8 - bits);
        return word;
    }
    /* a run-time shift: whole bytes, then the 0..7 bits by an ASR/ROR loop */
    const int bytes = shift / 8;
    if (bytes == 1) {
        low = (low >> 8) | (high << 24);
        high >>= 8;
    } else if (bytes == 2) {
        low = (low >> 16) | (high << 16);
        high >>= 16;
    } else if (bytes == 3) {
        low = (low >> 24) | (high << 8);
        high >>= 24;
    }
    FC_AVR_ASR64(low, high, shift % 8);
    return low;
}

/* fc_fx_low16_asr: for a constant shift of 12..15 the three high bytes of
 * t shifted left by 16 - shift bits (LSL/ROL, 3 cycles a bit), their upper
 * two the result; the 32-bit shift would form and sign-extend the two
 * bytes the 16-bit result drops. Other shifts as the portable form. */
#define FC_PORT_LOW16_ASR
#define FC_AVR_SHL24_1 "lsl %0\n\trol %1\n\trol %2\n\t"
FC_FX_INLINE int16_t fc_fx_low16_asr(uint32_t t, int shift)
{
    if (__builtin_constant_p(shift) && shift >= 12 && shift <= 15) {
        uint8_t b1 = (uint8_t)(t >> 8), b2 = (uint8_t)(t >> 16), b3 = (uint8_t)(t >> 24);
        switch (16 - shift) {
        case 1: __asm__(FC_AVR_SHL24_1 : "+r"(b1), "+r"(b2), "+r"(b3)); break;
        case 2: __asm__(FC_AVR_SHL24_1 FC_AVR_SHL24_1 : "+r"(b1), "+r"(b2), "+r"(b3)); break;
        case 3: __asm__(FC_AVR_SHL24_1 FC_AVR_SHL24_1 FC_AVR_SHL24_1 : "+r"(b1), "+r"(b2), "+r"(b3)); break;
        default:
            __asm__(FC_AVR_SHL24_1 FC_AVR_SHL24_1 FC_AVR_SHL24_1 FC_AVR_SHL24_1 : "+r"(b1), "+r"(b2), "+r"(b3));
            break;
        }
        return (int16_t)(uint16_t)((uint16_t)b2 | (uint16_t)((uint16_t)b3 << 8));
    }
    return (int16_t)fc_fx_asr32((int32_t)t, shift);
}

/* fc_fx_asr32, fc_fx_shl32: a constant shift by bytes and a few bits
 * (fc_fx_extract), not by a C shift, a loop at -Os */
FC_FX_INLINE int32_t fc_fx_asr32(int32_t a, int n)
{
    if (__builtin_constant_p(n) && n > 0) {
        const uint32_t sign = a < 0 ? UINT32_MAX : 0u;
        return (int32_t)fc_fx_extract((uint32_t)a, sign, n);
    }
    return a >> n;
}

FC_FX_INLINE int32_t fc_fx_shl32(int32_t a, int n)
{
    if (__builtin_constant_p(n) && n > 0) {
        return (int32_t)fc_fx_extract(0u, (uint32_t)a, 32 - n);
    }
    return (int32_t)((uint32_t)a << n);
}

/* fc_fx_halve_rounded: ASR/ROR, and the bit shifted out (the carry) added
 * back by ADC (avr-gcc masks the low bit and adds it as a 32-bit value) */
#define FC_PORT_HALVE_ROUNDED
FC_FX_INLINE int32_t fc_fx_halve_rounded(int32_t h)
{
    __asm__("asr %D0\n\tror %C0\n\tror %B0\n\tror %A0\n\t"
            "adc %A0, __zero_reg__\n\tadc %B0, __zero_reg__\n\tadc %C0, __zero_reg__\n\tadc %D0, __zero_reg__"
            : "+r"(h));
    return h;
}

/* fc_fx_round_asr32: for a constant n whose last byte's bits are 0 or 5..7,
 * the word above the byte that holds bit n - 1 shifted left by 8 - n % 8
 * bits (none for n % 8 = 0) out of that byte, whose next bit, bit n - 1 of
 * a, is then shifted into the carry and added (ADC); other shifts as the
 * portable form (fc_fx_asr32 by n - 1 is then no longer than by n) */
#define FC_PORT_ROUND_ASR32
FC_FX_INLINE int32_t fc_fx_round_asr32(int32_t a, int n)
{
    if (__builtin_constant_p(n) && n >= 5 && (n % 8 == 0 || n % 8 >= 5)) {
        const uint32_t sign = a < 0 ? UINT32_MAX : 0u;
        const int bytes = (n - 1) / 8;
        uint32_t word = fc_avr_word((uint32_t)a, sign, bytes + 1);
        uint8_t bottom = fc_avr_byte((uint32_t)a, sign, bytes);
        FC_AVR_SHL40(word, bottom, (8 - n % 8) % 8);
        __asm__("lsl %1\n\t"
                "adc %A0, __zero_reg__\n\tadc %B0, __zero_reg__\n\tadc %C0, __zero_reg__\n\tadc %D0, __zero_reg__"
                : "+r"(word), "+r"(bottom));
        return (int32_t)word;
    }
    return fc_fx_halve_rounded(fc_fx_asr32(a, n - 1));
}

/* fc_fx_asr_wide: by ASR/ROR, unrolled for a compile-time constant and a
 * counted loop for a run-time one */
FC_FX_INLINE fc_fx_wide fc_fx_asr_wide(fc_fx_wide value, int bits)
{
    FC_AVR_ASR64(value.low, value.high, bits);
    return value;
}

/* fc_fx_add64 on halves: a + b, clamped at +-INT64_MAX. */
FC_FX_INLINE fc_fx_wide fc_fx_add_wide(fc_fx_wide a, fc_fx_wide b)
{
    fc_fx_wide sum;
    sum.low = a.low + b.low;
    sum.high = a.high + b.high + (sum.low < a.low ? 1u : 0u);
    /* signed overflow: both operands of one sign, the sum of the other */
    if ((int32_t)(~(a.high ^ b.high) & (a.high ^ sum.high)) < 0) {
        const bool positive = (int32_t)a.high >= 0;
        sum.low = positive ? UINT32_MAX : 1u;
        sum.high = positive ? (uint32_t)INT32_MAX : (uint32_t)INT32_MIN;
    }
    return sum;
}

/*
 * fc_fx_narrow_wide for 32 <= shift <= FC_FX_FAR_SHIFT_MAX: the products whose
 * formats drop 32 bits or more (RATE x RATE -> GAIN, UNIT x UNIT -> ANGLE,
 * VEL x DT -> LENGTH). The value is floored by 2^k, k = shift - 31, then
 * rounded by 2^31:
 *   floor((floor(v / 2^k) + 2^30) / 2^31) = floor((v + 2^(shift-1)) / 2^shift)
 * (v = 2^k q + r with 0 <= r < 2^k: r / 2^k < 1 added to the integer
 * q + 2^30 leaves the floor as it is), so the value and the saturation are
 * those of fc_fx_narrow.
 */
#define FC_FX_FAR_SHIFT_MAX 38
FC_FX_INLINE fc_real fc_fx_narrow_wide_far(fc_arith *ar, fc_fx_wide value, int shift)
{
    return fc_fx_narrow_wide(ar, fc_fx_asr_wide(value, shift - 31), 31);
}

/* fc_fx_narrow_sum's form for the shifts 32..FC_FX_FAR_SHIFT_MAX + 2, on the
 * halves: QUARTERS is the sum of the products each floored by 4 (four of
 * them sum without a clamp), narrowed by shift - 2. */
FC_FX_INLINE fc_real fc_fx_narrow_quarters(fc_arith *ar, fc_fx_wide quarters, int shift)
{
    if (shift - 2 < 32) {
        return fc_fx_narrow_wide(ar, quarters, shift - 2);
    }
    return fc_fx_narrow_wide_far(ar, quarters, shift - 2);
}

/* a * b floored by 4, as halves (a term of fc_fx_narrow_quarters), and the
 * sums of two, three and four of them in fc_fx_narrow_sum's order. */
FC_FX_INLINE fc_fx_wide fc_fx_mul_quarter(int32_t a, int32_t b)
{
    return fc_fx_asr_wide(fc_fx_mul_wide(a, b), 2);
}

FC_FX_INLINE fc_fx_wide fc_fx_quarters2(int32_t a0, int32_t b0, int32_t a1, int32_t b1)
{
    return fc_fx_add_wide_wrap(fc_fx_mul_quarter(a0, b0), fc_fx_mul_quarter(a1, b1));
}

FC_FX_INLINE fc_fx_wide fc_fx_quarters3(int32_t a0, int32_t b0, int32_t a1, int32_t b1, int32_t a2, int32_t b2)
{
    return fc_fx_add_wide_wrap(fc_fx_quarters2(a0, b0, a1, b1), fc_fx_mul_quarter(a2, b2));
}

FC_FX_INLINE fc_fx_wide fc_fx_quarters4(int32_t a0, int32_t b0, int32_t a1, int32_t b1, int32_t a2, int32_t b2,
                                        int32_t a3, int32_t b3)
{
    return fc_fx_add_wide_wrap(fc_fx_quarters2(a0, b0, a1, b1), fc_fx_quarters2(a2, b2, a3, b3));
}

/* ======================================================================= */
/* fc_mul16 (FC_PORT_MUL16), fc_add and fc_sub (FC_PORT_ADD)              */
/* ======================================================================= */

/* fc_mul16: the signed 16 x 16 -> 32 product inline, the inner loop's most
 * frequent operation (avr-gcc calls libgcc's __mulhisi3, which forms the
 * unsigned product and corrects its signs after a call): MULS of the high
 * bytes, MUL of the low ones, and the two cross products by MULSU, each
 * sign-extended into the top byte by SBC of its carry (the method of Atmel's
 * AVR201 application note). MULS and MULSU take their operands in r16-r23
 * ("a"). */
#define FC_PORT_MUL16
static inline __attribute__((always_inline)) int32_t fc_mul16(int16_t a, int16_t b)
{
    int32_t product;
    uint8_t zero;
    __asm__("clr %1\n\t"
            "muls %B2, %B3\n\t"
            "movw %C0, r0\n\t"
            "mul %A2, %A3\n\t"
            "movw %A0, r0\n\t"
            "mulsu %B2, %A3\n\t"
            "sbc %D0, %1\n\t"
            "add %B0, r0\n\t"
            "adc %C0, r1\n\t"
            "adc %D0, %1\n\t"
            "mulsu %B3, %A2\n\t"
            "sbc %D0, %1\n\t"
            "add %B0, r0\n\t"
            "adc %C0, r1\n\t"
            "adc %D0, %1\n\t"
            "clr __zero_reg__"
            : "=&r"(product), "=&r"(zero)
            : "a"(a), "a"(b));
    return product;
}

/* fc_sq16: a a by MULS of the high byte, MUL of the low one and the cross
 * product by one MULSU, added twice (its sign byte formed by SBC of its
 * carry) */
#define FC_PORT_SQ16
static inline __attribute__((always_inline)) int32_t fc_sq16(int16_t a)
{
    int32_t product;
    uint8_t sign;
    __asm__("muls %B2, %B2\n\t"
            "movw %C0, r0\n\t"
            "mul %A2, %A2\n\t"
            "movw %A0, r0\n\t"
            "mulsu %B2, %A2\n\t"
            "sbc %1, %1\n\t"
            "add %B0, r0\n\t"
            "adc %C0, r1\n\t"
            "adc %D0, %1\n\t"
            "add %B0, r0\n\t"
            "adc %C0, r1\n\t"
            "adc %D0, %1\n\t"
            "clr __zero_reg__"
            : "=&r"(product), "=&r"(sign)
            : "a"(a));
    return product;
}

/* fc_mul16_unsigned: the same with a unsigned (avr-gcc widens both to 32
 * bits and calls __mulsi3): MULSU of b's high byte by each byte of a, MUL of
 * the low bytes and of a's high byte by b's low one */
static inline __attribute__((always_inline)) int32_t fc_mul16_unsigned(uint16_t a, int16_t b)
{
    int32_t product;
    uint8_t zero;
    __asm__("clr %1\n\t"
            "mulsu %B3, %B2\n\t"
            "movw %C0, r0\n\t"
            "mul %A2, %A3\n\t"
            "movw %A0, r0\n\t"
            "mulsu %B3, %A2\n\t"
            "sbc %D0, %1\n\t"
            "add %B0, r0\n\t"
            "adc %C0, r1\n\t"
            "adc %D0, %1\n\t"
            "mul %B2, %A3\n\t"
            "add %B0, r0\n\t"
            "adc %C0, r1\n\t"
            "adc %D0, %1\n\t"
            "clr __zero_reg__"
            : "=&r"(product), "=&r"(zero)
            : "a"(a), "a"(b));
    return product;
}

/* fc_umul16: the unsigned 16 x 16 -> 32 product inline (avr-gcc calls
 * libgcc's __umulhisi3, or widens an operand and calls __mulsi3): MUL of the
 * low bytes and of the high ones into the two halves, then the two cross
 * products added at byte 1 (no carry leaves byte 3: the product is below
 * 2^32) */
static inline __attribute__((always_inline)) uint32_t fc_umul16(uint16_t a, uint16_t b)
{
    uint32_t product;
    uint8_t zero;
    __asm__("clr %1\n\t"
            "mul %A2, %A3\n\t"
            "movw %A0, r0\n\t"
            "mul %B2, %B3\n\t"
            "movw %C0, r0\n\t"
            "mul %A2, %B3\n\t"
            "add %B0, r0\n\t"
            "adc %C0, r1\n\t"
            "adc %D0, %1\n\t"
            "mul %B2, %A3\n\t"
            "add %B0, r0\n\t"
            "adc %C0, r1\n\t"
            "adc %D0, %1\n\t"
            "clr __zero_reg__"
            : "=&r"(product), "=&r"(zero)
            : "r"(a), "r"(b));
    return product;
}

/* fc_add, fc_sub: the 32-bit sum by ADD/ADC (SUB/SBC) and the overflow read
 * from the V flag (avr-gcc 5.4 forms __builtin_add_overflow by comparing the
 * sum with an operand, and the symmetric range's -2^31 by a second compare
 * chain). The sum is -2^31 iff sum - 1 overflows: one compare with FLAG,
 * which holds the 1. On overflow the wrapped sum has the sign opposite to
 * the true one: +INT32_MAX when it reads negative (its sign byte spread over
 * the four, the top bit flipped), -INT32_MAX when it reads positive (the
 * same gives -2^31, then one more: the INC shared with the -2^31 case,
 * skipped when the top bit reads +INT32_MAX). OP is "add"/"sub" and CARRY
 * "adc"/"sbc".
 * FLAG (r16-r31, for LDI) is 1 when it saturated, else 0. */
#define FC_AVR_ADD_SATURATED(OP, CARRY)                                                        \
    OP " %A0, %A2\n\t" CARRY " %B0, %B2\n\t" CARRY " %C0, %C2\n\t" CARRY " %D0, %D2\n\t"        \
    "ldi %1, 1\n\t"                                                                            \
    "brvs 1f\n\t"                                                                              \
    "cp %A0, %1\n\tcpc %B0, __zero_reg__\n\tcpc %C0, __zero_reg__\n\tcpc %D0, __zero_reg__\n\t"   \
    "brvs 2f\n\t"                                                                              \
    "clr %1\n\t"                                                                               \
    "rjmp 3f\n"                                                                                \
    "1:\n\tlsl %D0\n\tsbc %A0, %A0\n\tmov %B0, %A0\n\tmovw %C0, %A0\n\t"                       \
    "ldi %1, 0x80\n\teor %D0, %1\n\tldi %1, 1\n\tsbrc %D0, 7\n"                                \
    "2:\n\tinc %A0\n"                                                                          \
    "3:"

/* the saturation of FC_AVR_ADD_SATURATED (1 or 0) recorded in the caller's record */
FC_FX_INLINE fc_real fc_avr_recorded(fc_arith *ar, fc_real value, uint8_t saturated)
{
    if (saturated != 0u) {
        ar->saturated = saturated;
    }
    return value;
}

#define FC_PORT_ADD
FC_FX_INLINE fc_real fc_add_inline(fc_arith *ar, fc_real a, fc_real b)
{
    fc_real sum = a;
    uint8_t saturated;
    __asm__(FC_AVR_ADD_SATURATED("add", "adc") : "+r"(sum), "=&d"(saturated) : "r"(b));
    return fc_avr_recorded(ar, sum, saturated);
}

FC_FX_INLINE fc_real fc_sub_inline(fc_arith *ar, fc_real a, fc_real b)
{
    fc_real difference = a;
    uint8_t saturated;
    __asm__(FC_AVR_ADD_SATURATED("sub", "sbc") : "+r"(difference), "=&d"(saturated) : "r"(b));
    return fc_avr_recorded(ar, difference, saturated);
}

/* fc_add, fc_sub: the same assembly out of line (scalar.c, FC_AVR_ADD_CALLED),
 * called with the operands in the registers it names: a (the result) in
 * r22-r25, b in r18-r21, &ar->saturated in Z; it changes only r22-r25, r0
 * and the record (hence the memory clobber). The call, a few register moves
 * and the clobber in place of the inlined sum and its record: most sums run
 * at init, on the rare paths or not at every step, where flash counts and
 * cycles do not; the others are written fc_add_inline / fc_sub_inline. */
#define FC_AVR_ADD_CALL(NAME, A, B, AR)                                                         \
    do {                                                                                       \
        register fc_real fc_avr_a_ __asm__("r22") = (A);                                        \
        register fc_real fc_avr_b_ __asm__("r18") = (B);                                        \
        register uint8_t *fc_avr_record_ __asm__("r30") = &(AR)->saturated;                     \
        __asm__("call " NAME : "+r"(fc_avr_a_) : "r"(fc_avr_b_), "r"(fc_avr_record_) : "memory"); \
        (A) = fc_avr_a_;                                                                       \
    } while (0)

FC_FX_INLINE fc_real fc_add(fc_arith *ar, fc_real a, fc_real b)
{
    FC_AVR_ADD_CALL("fc_fx_add_avr", a, b, ar);
    return a;
}

FC_FX_INLINE fc_real fc_sub(fc_arith *ar, fc_real a, fc_real b)
{
    FC_AVR_ADD_CALL("fc_fx_sub_avr", a, b, ar);
    return a;
}

/* ======================================================================= */
/* fc_mul, fc_dotN (FC_PORT_PRODUCTS) and fc_acc_mac (FC_PORT_ACC_MAC)     */
/* ======================================================================= */
#define FC_PORT_PRODUCTS

/* fc_mul_inline and fc_dot2_inline: on the halves, inline (the sites that
 * run so often that the call, its register saves and the run-time shift
 * matter more than the flash of the inlined product) */
FC_FX_INLINE fc_real fc_mul_inline(fc_arith *ar, fc_real a, fc_real b, int shift)
{
    if (shift > 0 && shift < 32) {
        return fc_fx_narrow_wide(ar, fc_fx_mul_wide(a, b), shift);
    }
    if (shift >= 32 && shift <= FC_FX_FAR_SHIFT_MAX) {
        return fc_fx_narrow_wide_far(ar, fc_fx_mul_wide(a, b), shift);
    }
    return fc_fx_narrow(ar, (int64_t)a * b, shift);
}

FC_FX_INLINE fc_real fc_dot2_inline(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, int shift)
{
    if (shift > 0 && shift < 32) {
        return fc_fx_narrow_wide(ar, fc_fx_add_wide(fc_fx_mul_wide(a0, b0), fc_fx_mul_wide(a1, b1)), shift);
    }
    if (shift >= 32 && shift <= FC_FX_FAR_SHIFT_MAX + 2) {
        return fc_fx_narrow_quarters(ar, fc_fx_quarters2(a0, b0, a1, b1), shift);
    }
    return fc_fx_narrow_sum(ar, (int64_t)a0 * b0, (int64_t)a1 * b1, 0, 0, shift);
}

/* fc_mul and fc_dotN: one out-of-line copy each (scalar.c, the shift at run
 * time): inlined at every site they overflow the flash, and the inner
 * loop's frequent products are the 16-bit ones, inline everywhere */
fc_real fc_fx_mul_outline(fc_arith *ar, fc_real a, fc_real b, int shift);
fc_real fc_fx_dot2_outline(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, int shift);
fc_real fc_fx_dot3_outline(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, fc_real a2, fc_real b2,
                           int shift);
fc_real fc_fx_dot4_outline(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, fc_real a2, fc_real b2,
                           fc_real a3, fc_real b3, int shift);

FC_FX_INLINE fc_real fc_mul(fc_arith *ar, fc_real a, fc_real b, int shift)
{
    return fc_fx_mul_outline(ar, a, b, shift);
}

FC_FX_INLINE fc_real fc_dot2(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, int shift)
{
    return fc_fx_dot2_outline(ar, a0, b0, a1, b1, shift);
}

FC_FX_INLINE fc_real fc_dot3(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, fc_real a2, fc_real b2,
                             int shift)
{
    return fc_fx_dot3_outline(ar, a0, b0, a1, b1, a2, b2, shift);
}

FC_FX_INLINE fc_real fc_dot4(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, fc_real a2, fc_real b2,
                             fc_real a3, fc_real b3, int shift)
{
    return fc_fx_dot4_outline(ar, a0, b0, a1, b1, a2, b2, a3, b3, shift);
}

/* fc_acc_mac out of line (scalar.c): the multiply, shift and 64-bit add of
 * a term inlined at every site of the matrix loops cost far more flash than
 * the call costs cycles */
#define FC_PORT_ACC_MAC
fc_acc fc_acc_mac(fc_acc acc, fc_real a, fc_real b);

/* ======================================================================= */
/* fc_narrow16 (FC_PORT_NARROW16)                                          */
/* ======================================================================= */

/* fc_narrow16: a shift of 16 is the high half plus bit 15 for the rounding
 * (no 32-bit shift) */
#define FC_PORT_NARROW16
FC_FX_INLINE fc_real fc_convert(fc_arith *ar, fc_real a, int frac_from, int frac_to); /* fc/scalar.h */
FC_FX_INLINE fc_real16 fc_narrow16(fc_arith *ar, fc_real x, int frac_from, int frac_to)
{
    if (frac_from - frac_to == 16) {
        const int16_t high = (int16_t)(uint16_t)((uint32_t)x >> 16);
        const bool up = ((uint32_t)x & 0x8000u) != 0u;
        if ((up && high == INT16_MAX) || (!up && high == INT16_MIN)) {
            ar->saturated = 1u;
            return high < 0 ? -FC_REAL16_MAX : FC_REAL16_MAX;
        }
        return (fc_real16)(high + (up ? 1 : 0));
    }
    const int shift = frac_from - frac_to;
    if (shift == 12 || shift == 14) {
        /* the rounded value leaves +-FC_REAL16_MAX iff x >= (2^16 - 1)
         * 2^(shift - 1) or x < -(2^16 - 1) 2^(shift - 1); inside, bits
         * shift.. of x + 2^(shift - 1) by fc_fx_low16_asr (no 32-bit
         * shift, no sign byte). At 13 and 15 fc_convert's form, whole
         * bytes and 3 or 1 bits, is as short. */
        const fc_real bound = (fc_real)(((uint32_t)1u << 16) - 1u) << (shift - 1);
        if (x >= bound || x < -bound) {
            ar->saturated = 1u;
            return x > 0 ? FC_REAL16_MAX : -FC_REAL16_MAX;
        }
        return fc_fx_low16_asr((uint32_t)x + ((uint32_t)1u << (shift - 1)), shift);
    }
    const fc_real r = frac_from == frac_to ? x : fc_convert(ar, x, frac_from, frac_to);
    if (r > FC_REAL16_MAX || r < -FC_REAL16_MAX) {
        ar->saturated = 1u;
        return r > 0 ? FC_REAL16_MAX : -FC_REAL16_MAX;
    }
    return (fc_real16)r;
}

/* ======================================================================= */
/* fc_mul_gain: a signal times a gain fixed at init (fc/scalar.h, fc_gain)  */
/* ======================================================================= */
/*
 * x m / 2^shift rounded and saturated, x 32-bit, m the gain's 16-bit
 * mantissa, shift = the gain's frac + FC_GAIN_SHIFT(...), known only at run
 * time: one out-of-line function in assembly (scalar.c, naked), with the
 * registers of the calling convention alone, so nothing is saved:
 *   in   x r22-r25, m r20-r21, shift r18, ar r16-r17 (read only)
 *   out  r22-r25
 * Shifts outside 1..46 go to the portable definition (fc_fx_mul_gain_avr_far,
 * a tail call). Otherwise, as fc_mul_by16: x = 2^16 x_high + x_low,
 *   L = x_low m        (x_low unsigned: MUL, MULSU; fc_mul16_unsigned's steps)
 *   t = x_high m + floor(L / 2^16) = floor(x m / 2^16),  |t| < 2^30 + 2^15
 * (x_high m by MULS/MULSU added onto L's high half sign-extended: fc_mul16's
 * steps), then the shift, whole bytes by moves and the 0..7 bits left by an
 * ASR/ROR loop (for shift <= 16, 5..7 bits as 3..1 bits left by LSL/ROL of
 * the bytes and a sign byte above them, whose top bytes are then taken):
 *   shift > 16   floor((x m + 2^(shift-1)) / 2^shift)
 *                = floor((t + 2^(shift-17)) / 2^(shift-16))  (x m's bits below
 *                2^16 cannot carry into 2^(shift-16))
 *                = (floor(t / 2^(shift-17)) + 1) >> 1, on t alone, never
 *                beyond the range;
 *   shift <= 16  w = floor(x m / 2^(shift-1)) on the 48 bits t:L_low, the
 *                result (w + 1) >> 1, inside +-INT32_MAX iff w + 1 is in
 *                [-2^32 + 2, 2^32 - 1]: its bits 32..47 all 0, or all 1 and
 *                its low 32 bits not 0 or 1 (the result -2^31).
 * The same value and saturation as fc_fx_mul_gain_reference
 * (atmega.scalar_equivalence).
 * Registers: x_high moves to r18:r19 and shift - 1 to r30 (MULS and MULSU
 * take r16-r23); L in r24-r27, r31 the zero; t = r23:r22:r27:r26 (x_low's
 * place once L is formed), L_low r25:r24.
 */
#define FC_AVR_MUL_GAIN_BODY                                                                   \
    "mov r30, r18\n\t"                                                                         \
    "subi r30, 1\n\t"                                                                          \
    "cpi r30, 46\n\t"                                                                          \
    "brlo 1f\n\t"                                                                              \
    "jmp fc_fx_mul_gain_avr_far\n"                                                             \
    "1:\n\t"                                                                                   \
    "movw r18, r24\n\t"                                                                        \
    /* L = x_low m: r27:r26:r25:r24 */                                                         \
    "clr r31\n\t"                                                                              \
    "mulsu r21, r23\n\t"                                                                       \
    "movw r26, r0\n\t"                                                                         \
    "mul r22, r20\n\t"                                                                         \
    "movw r24, r0\n\t"                                                                         \
    "mulsu r21, r22\n\t"                                                                       \
    "sbc r27, r31\n\t"                                                                         \
    "add r25, r0\n\t"                                                                          \
    "adc r26, r1\n\t"                                                                          \
    "adc r27, r31\n\t"                                                                         \
    "mul r23, r20\n\t"                                                                         \
    "add r25, r0\n\t"                                                                          \
    "adc r26, r1\n\t"                                                                          \
    "adc r27, r31\n\t"                                                                         \
    /* t = L's high half sign-extended (r23:r22:r27:r26) + x_high m */                         \
    "mov r22, r27\n\t"                                                                         \
    "lsl r22\n\t"                                                                              \
    "sbc r22, r22\n\t"                                                                         \
    "mov r23, r22\n\t"                                                                         \
    "mul r18, r20\n\t"                                                                         \
    "add r26, r0\n\t"                                                                          \
    "adc r27, r1\n\t"                                                                          \
    "adc r22, r31\n\t"                                                                         \
    "adc r23, r31\n\t"                                                                         \
    "mulsu r19, r20\n\t"                                                                       \
    "sbc r23, r31\n\t"                                                                         \
    "add r27, r0\n\t"                                                                          \
    "adc r22, r1\n\t"                                                                          \
    "adc r23, r31\n\t"                                                                         \
    "mulsu r21, r18\n\t"                                                                       \
    "sbc r23, r31\n\t"                                                                         \
    "add r27, r0\n\t"                                                                          \
    "adc r22, r1\n\t"                                                                          \
    "adc r23, r31\n\t"                                                                         \
    "muls r19, r21\n\t"                                                                        \
    "add r22, r0\n\t"                                                                          \
    "adc r23, r1\n\t"                                                                          \
    "clr r1\n\t"                                                                               \
    "cpi r30, 16\n\t"                                                                          \
    "brlo 20f\n\t"                                                                             \
    /* shift > 16: k = shift - 17, t's bytes k / 8 on into r25:r24:r23:r22 */                 \
    "subi r30, 16\n\t"                                                                         \
    "cpi r30, 8\n\t"                                                                           \
    "brsh 11f\n\t"                                                                             \
    "movw r24, r22\n\t"                                                                        \
    "movw r22, r26\n\t"                                                                        \
    "rjmp 14f\n"                                                                               \
    "11:\n\t"                                                                                  \
    "cpi r30, 16\n\t"                                                                          \
    "brsh 12f\n\t"                                                                             \
    "mov r24, r23\n\t"                                                                         \
    "mov r25, r23\n\t"                                                                         \
    "lsl r25\n\t"                                                                              \
    "sbc r25, r25\n\t"                                                                         \
    "mov r23, r22\n\t"                                                                         \
    "mov r22, r27\n\t"                                                                         \
    "rjmp 14f\n"                                                                               \
    "12:\n\t"                                                                                  \
    "cpi r30, 24\n\t"                                                                          \
    "brsh 13f\n\t"                                                                             \
    "mov r24, r23\n\t"                                                                         \
    "lsl r24\n\t"                                                                              \
    "sbc r24, r24\n\t"                                                                         \
    "mov r25, r24\n\t"                                                                         \
    "rjmp 14f\n"                                                                               \
    "13:\n\t"                                                                                  \
    "mov r22, r23\n\t"                                                                         \
    "lsl r23\n\t"                                                                              \
    "sbc r23, r23\n\t"                                                                         \
    "mov r24, r23\n\t"                                                                         \
    "mov r25, r23\n"                                                                           \
    "14:\n\t"                                                                                  \
    "andi r30, 7\n\t"                                                                          \
    "breq 16f\n\t"                                                                             \
    "cpi r30, 5\n\t"                                                                           \
    "brlo 15f\n\t"                                                                             \
    "rjmp 17f\n"                                                                               \
    "15:\n\t"                                                                                  \
    "asr r25\n\tror r24\n\tror r23\n\tror r22\n\t"                                             \
    "dec r30\n\t"                                                                              \
    "brne 15b\n"                                                                               \
    "16:\n\t"                                                                                  \
    /* (w >> 1) + (w & 1): the bit shifted out is the carry */                                 \
    "asr r25\n\tror r24\n\tror r23\n\tror r22\n\t"                                             \
    "adc r22, r1\n\tadc r23, r1\n\tadc r24, r1\n\tadc r25, r1\n\t"                             \
    "ret\n"                                                                                    \
    /* shift <= 16: the 48 bits r23:r22:r27:r26:r25:r24 by shift - 1 */                        \
    "20:\n\t"                                                                                  \
    "cpi r30, 8\n\t"                                                                           \
    "brlo 21f\n\t"                                                                             \
    "mov r24, r25\n\t"                                                                         \
    "mov r25, r26\n\t"                                                                         \
    "mov r26, r27\n\t"                                                                         \
    "mov r27, r22\n\t"                                                                         \
    "mov r22, r23\n\t"                                                                         \
    "lsl r23\n\t"                                                                              \
    "sbc r23, r23\n\t"                                                                         \
    "subi r30, 8\n"                                                                            \
    "21:\n\t"                                                                                  \
    "tst r30\n\t"                                                                              \
    "breq 23f\n\t"                                                                             \
    "cpi r30, 5\n\t"                                                                           \
    "brsh 25f\n"                                                                               \
    "22:\n\t"                                                                                  \
    "asr r23\n\tror r22\n\tror r27\n\tror r26\n\tror r25\n\tror r24\n\t"                       \
    "dec r30\n\t"                                                                              \
    "brne 22b\n"                                                                               \
    "23:\n\t"                                                                                  \
    /* v = w + 1 */                                                                            \
    "sec\n\t"                                                                                  \
    "adc r24, r1\n\tadc r25, r1\n\tadc r26, r1\n\tadc r27, r1\n\tadc r22, r1\n\tadc r23, r1\n\t" \
    /* bits 32..47 of v (r23:r22) all 0, or all 1 and the low 32 bits not 0 or 1 */           \
    "cp r22, r23\n\t"                                                                          \
    "brne 30f\n\t"                                                                             \
    "mov r30, r22\n\t"                                                                         \
    "inc r30\n\t"                                                                              \
    "lsr r30\n\t"                                                                              \
    "brne 30f\n\t"                                                                             \
    "tst r22\n\t"                                                                              \
    "breq 24f\n\t"                                                                             \
    "mov r30, r24\n\t"                                                                         \
    "lsr r30\n\t"                                                                              \
    "or r30, r25\n\t"                                                                          \
    "or r30, r26\n\t"                                                                          \
    "or r30, r27\n\t"                                                                          \
    "breq 30f\n"                                                                               \
    "24:\n\t"                                                                                  \
    /* the result, bits 1..32 of v, into r25:r22 */                                            \
    "asr r22\n\t"                                                                              \
    "ror r27\n\tror r26\n\tror r25\n\tror r24\n\t"                                             \
    "movw r22, r24\n\t"                                                                        \
    "movw r24, r26\n\t"                                                                        \
    "ret\n"                                                                                    \
    /* 5..7 bits: 8 - j bits right, j = 8 - bits in 1..3, as j bits left of */                 \
    /* the 7 bytes r21 (the sign):r23..r24 and their top 6 */                                  \
    "25:\n\t"                                                                                  \
    "mov r21, r23\n\tlsl r21\n\tsbc r21, r21\n\t"                                              \
    "cpi r30, 7\n\t"                                                                           \
    "breq 27f\n\t"                                                                             \
    "cpi r30, 6\n\t"                                                                           \
    "breq 26f\n\t"                                                                             \
    "lsl r24\n\trol r25\n\trol r26\n\trol r27\n\t"                                             \
    "rol r22\n\trol r23\n\trol r21\n"                                                          \
    "26:\n\t"                                                                                  \
    "lsl r24\n\trol r25\n\trol r26\n\trol r27\n\t"                                             \
    "rol r22\n\trol r23\n\trol r21\n"                                                          \
    "27:\n\t"                                                                                  \
    "lsl r24\n\trol r25\n\trol r26\n\trol r27\n\t"                                             \
    "rol r22\n\trol r23\n\trol r21\n\t"                                                        \
    "mov r24, r25\n\tmov r25, r26\n\tmov r26, r27\n\t"                                         \
    "mov r27, r22\n\tmov r22, r23\n\tmov r23, r21\n\t"                                         \
    "rjmp 23b\n"                                                                               \
    /* saturated: ar->saturated = 1, +-INT32_MAX by the sign of v */                           \
    "30:\n\t"                                                                                  \
    "movw r30, r16\n\t"                                                                        \
    "ldi r18, 1\n\t"                                                                           \
    "st Z, r18\n\t"                                                                            \
    "sbrc r23, 7\n\t"                                                                          \
    "rjmp 31f\n\t"                                                                             \
    "ldi r22, 0xFF\n\tldi r23, 0xFF\n\tldi r24, 0xFF\n\tldi r25, 0x7F\n\t"                     \
    "ret\n"                                                                                    \
    "31:\n\t"                                                                                  \
    "ldi r22, 0x01\n\tldi r23, 0\n\tldi r24, 0\n\tldi r25, 0x80\n\t"                           \
    "ret\n"                                                                                    \
    /* 5..7 bits: w >> 1 = the top 4 of the 5 bytes r21 (the sign):r25..r22 */                 \
    /* shifted left by 7 - bits in 0..2, w & 1 the top bit of the byte dropped */              \
    "17:\n\t"                                                                                  \
    "mov r21, r25\n\tlsl r21\n\tsbc r21, r21\n\t"                                              \
    "cpi r30, 7\n\t"                                                                           \
    "breq 19f\n\t"                                                                             \
    "cpi r30, 6\n\t"                                                                           \
    "breq 18f\n\t"                                                                             \
    "lsl r22\n\trol r23\n\trol r24\n\trol r25\n\trol r21\n"                                   \
    "18:\n\t"                                                                                  \
    "lsl r22\n\trol r23\n\trol r24\n\trol r25\n\trol r21\n"                                   \
    "19:\n\t"                                                                                  \
    "lsl r22\n\t"                                                                              \
    "mov r22, r23\n\tmov r23, r24\n\tmov r24, r25\n\tmov r25, r21\n\t"                         \
    "adc r22, r1\n\tadc r23, r1\n\tadc r24, r1\n\tadc r25, r1\n\t"                             \
    "ret"

#define FC_PORT_MUL_GAIN
/* scalar.c: the assembly above, and the portable definition for the other shifts */
fc_real fc_fx_mul_gain_avr(fc_real x, int16_t mantissa, uint8_t shift, fc_arith *ar);
fc_real fc_fx_mul_gain_avr_far(fc_real x, int16_t mantissa, uint8_t shift, fc_arith *ar);
/* the shift frac + shift_in_out modulo 2^8, as the assembly reads it, formed
 * in one byte (avr-gcc adds the int sum in two) */
FC_FX_INLINE fc_real fc_fx_mul_gain_shift(fc_arith *ar, fc_real x, int16_t mantissa, int8_t frac, int shift_in_out)
{
    return fc_fx_mul_gain_avr(x, mantissa, (uint8_t)((uint8_t)frac + (uint8_t)shift_in_out), ar);
}
/* ======================================================================= */

#endif /* FC_SCALAR_AVR_H */
