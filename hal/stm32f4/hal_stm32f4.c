/**
 * @file hal_stm32f4.c
 * @brief hal.h on the STM32F405/407 (see stm32f4_hal.h for the peripheral plan). Register
 *        names are RM0090's (stm32f4_regs.h). No heap; all state is file-static.
 */
#include "hal.h"

#include <stddef.h>

#include "startup.h"
#include "stm32f4_board.h"
#include "stm32f4_hal.h"
#include "stm32f4_regs.h"
#include "tv_status.h"

/** Interrupt priority of the control tick and the CAN queues (0 = most urgent, 15 least). */
#define PRIO_CONTROL 1u
#define PRIO_CAN 1u

/** A software frame queue (single producer / single consumer, accessed with interrupts masked). */
typedef struct {
    hal_can_frame_t f[STM32F4_CAN_QUEUE_LEN];
    uint32_t head; /**< next to take */
    uint32_t n;    /**< frames held */
} can_queue_t;

static uint32_t s_pwm_arr;          /**< TIM1 auto-reload: half the PWM period in timer ticks */
static uint32_t s_time_hi;          /**< upper 32 bits of hal_time_us() */
static uint32_t s_time_last;        /**< TIM5 at the previous hal_time_us() */
static volatile uint32_t s_estop;   /**< 1 after stm32f4_emergency_stop() */
static uint32_t s_initialised;      /**< 1 after stm32f4_hal_init() succeeded */
static can_queue_t s_can_tx;
static can_queue_t s_can_rx;
static stm32f4_status_t s_status;
static uint32_t s_tick_phase_us;    /**< TIM2 start value: places the tick after a PWM peak */

/* ---- small helpers ------------------------------------------------------------------------ */

uint32_t stm32f4_irq_save(void)
{
    uint32_t primask;
    __asm__ volatile("mrs %0, primask\n\tcpsid i" : "=r"(primask)::"memory");
    return primask;
}

void stm32f4_irq_restore(uint32_t primask)
{
    __asm__ volatile("msr primask, %0" ::"r"(primask) : "memory");
}

static void nvic_enable(uint32_t irqn, uint32_t prio)
{
    NVIC_IPR[irqn] = (uint8_t)(prio << (8u - NVIC_PRIO_BITS));
    NVIC_ICPR[irqn >> 5] = 1u << (irqn & 31u);
    NVIC_ISER[irqn >> 5] = 1u << (irqn & 31u);
}

static void gpio_config(gpio_regs_t *port, uint32_t pin, uint32_t mode, uint32_t af, uint32_t pupd)
{
    const uint32_t sh2 = 2u * pin;
    const uint32_t sh4 = 4u * (pin & 7u);
    port->AFR[pin >> 3] = (port->AFR[pin >> 3] & ~(0xFu << sh4)) | (af << sh4);
    port->PUPDR = (port->PUPDR & ~(3u << sh2)) | (pupd << sh2);
    port->OSPEEDR = (port->OSPEEDR & ~(3u << sh2)) | (GPIO_OSPEEDR_HIGH << sh2);
    port->OTYPER &= ~(1u << pin);
    port->MODER = (port->MODER & ~(3u << sh2)) | (mode << sh2);
}

/* Busy-wait until (*reg & mask) == value or timeout_us elapsed on TIM5. @return 1 when met. */
static int wait_flag_us(const volatile uint32_t *reg, uint32_t mask, uint32_t value, uint32_t timeout_us)
{
    const uint32_t t0 = TIM5->CNT;
    do {
        if ((*reg & mask) == value) {
            return 1;
        }
    } while ((uint32_t)(TIM5->CNT - t0) < timeout_us);
    return (*reg & mask) == value;
}

/* ---- configuration ------------------------------------------------------------------------ */

void stm32f4_hal_config_default(stm32f4_hal_config_t *cfg)
{
    if (cfg != NULL) {
        cfg->pwm_frequency_Hz = STM32F4_PWM_DEFAULT_HZ;
        cfg->can_bitrate_bps = STM32F4_CAN_DEFAULT_BPS;
    }
}

/* TIM1 ARR for centre-aligned PWM: f = TIMCLK / (2 ARR). 0 when not exactly realisable. */
static uint32_t pwm_arr(uint32_t tim_Hz, uint32_t f_Hz)
{
    if (f_Hz < 2000u || f_Hz > 50000u || f_Hz % 1000u != 0u || tim_Hz % (2u * f_Hz) != 0u) {
        return 0u;
    }
    return tim_Hz / (2u * f_Hz);
}

/*
 * bxCAN bit timing (RM0090 section 32.7.7): bit = (1 + TS1 + TS2) time quanta of
 * (BRP + 1) / PCLK1. Takes the largest quanta count 8..25 that divides exactly, with the
 * sample point near 87.5 % (TS2 = quanta / 8, at least 2). @return BTR, or 0.
 */
static uint32_t can_btr(uint32_t pclk_Hz, uint32_t bps)
{
    uint32_t ntq;
    if (bps != 125000u && bps != 250000u && bps != 500000u && bps != 1000000u) {
        return 0u;
    }
    for (ntq = 25u; ntq >= 8u; --ntq) {
        if (pclk_Hz % (bps * ntq) == 0u && pclk_Hz / (bps * ntq) <= 1024u) {
            const uint32_t brp = pclk_Hz / (bps * ntq);
            const uint32_t ts2 = ntq / 8u < 2u ? 2u : ntq / 8u;
            const uint32_t ts1 = ntq - 1u - ts2;
            if (ts1 > 16u || ts2 > 8u) {
                continue;
            }
            /* SJW field 0: resynchronisation jump width 1 quantum. */
            return ((brp - 1u) << CAN_BTR_BRP_Pos) | ((ts1 - 1u) << CAN_BTR_TS1_Pos) |
                   ((ts2 - 1u) << CAN_BTR_TS2_Pos);
        }
    }
    return 0u;
}

static void pwm_init(void)
{
    TIM1->CR1 = 0u;
    TIM1->CR1 = TIM_CR1_CMS_CENTER1 | TIM_CR1_ARPE;
    TIM1->PSC = 0u;
    TIM1->ARR = s_pwm_arr;
    TIM1->RCR = 0u;
    /* IN1, IN2: PWM mode 2 (active while CNT > CCR): the pulse is centred on the peak; CCR >
     * ARR keeps the output inactive (0 %). CH4: PWM mode 1 with CCR4 = ARR - 1; in centre-
     * aligned mode 1 its compare event fires counting down, one tick after the peak: the ADC
     * trigger. */
    TIM1->CCMR1 = (TIM_OCM_PWM2 << TIM_CCMR1_OC1M_Pos) | TIM_CCMR1_OC1PE | (TIM_OCM_PWM2 << TIM_CCMR1_OC2M_Pos) |
                  TIM_CCMR1_OC2PE;
    TIM1->CCMR2 = (TIM_OCM_PWM1 << TIM_CCMR2_OC4M_Pos) | TIM_CCMR2_OC4PE;
    TIM1->CCR1 = s_pwm_arr + 1u;
    TIM1->CCR2 = s_pwm_arr + 1u;
    TIM1->CCR4 = s_pwm_arr - 1u;
    TIM1->CCER = TIM_CCER_CC1E | TIM_CCER_CC2E | TIM_CCER_CC4E;
    /* OSSI: with MOE = 0 the outputs are driven to their idle level (low) rather than released. */
    TIM1->BDTR = TIM_BDTR_OSSI | TIM_BDTR_OSSR;
    TIM1->EGR = TIM_EGR_UG;
    TIM1->SR = 0u;
    TIM1->BDTR |= TIM_BDTR_MOE;
    gpio_config(GPIOA, BOARD_PWM_IN1_PIN, GPIO_MODER_AF, BOARD_PWM_AF, 0u);
    gpio_config(GPIOA, BOARD_PWM_IN2_PIN, GPIO_MODER_AF, BOARD_PWM_AF, 0u);
}

static void adc_init(void)
{
    uint32_t k;
    gpio_config(GPIOA, BOARD_ADC_CH_CURRENT, GPIO_MODER_ANALOG, 0u, 0u);
    gpio_config(GPIOA, BOARD_ADC_CH_TPS1, GPIO_MODER_ANALOG, 0u, 0u);
    gpio_config(GPIOA, BOARD_ADC_CH_TPS2, GPIO_MODER_ANALOG, 0u, 0u);
    gpio_config(GPIOA, BOARD_ADC_CH_SUPPLY, GPIO_MODER_ANALOG, 0u, 0u);
    ADC_COMMON->CCR = ADC_CCR_ADCPRE_DIV4;
    ADC1->CR2 = 0u;
    ADC1->CR1 = ADC_CR1_SCAN; /* scan mode: the whole injected group per trigger */
    ADC1->SMPR2 = 0u;
    for (k = 0u; k < 4u; ++k) {
        ADC1->SMPR2 |= ADC_SMPR_15CYC << (3u * k);
    }
    /* JL = 3 (four conversions) runs JSQ1..JSQ4 in order: the current first, nearest the centre. */
    /* cppcheck-suppress badBitmaskCheck ; channel 0 in JSQ1 is a zero field, kept for the layout */
    ADC1->JSQR = (3u << ADC_JSQR_JL_Pos) | (BOARD_ADC_CH_CURRENT << ADC_JSQR_JSQ1_Pos) |
                 (BOARD_ADC_CH_TPS1 << ADC_JSQR_JSQ2_Pos) | (BOARD_ADC_CH_TPS2 << ADC_JSQR_JSQ3_Pos) |
                 (BOARD_ADC_CH_SUPPLY << ADC_JSQR_JSQ4_Pos);
    /* cppcheck-suppress badBitmaskCheck ; JEXTSEL = 0000 (TIM1 CC4) is a zero field, kept for the layout */
    ADC1->CR2 = (ADC_CR2_JEXTSEL_TIM1_CC4 << ADC_CR2_JEXTSEL_Pos) | ADC_CR2_JEXTEN_RISING | ADC_CR2_ADON;
    (void)wait_flag_us(&ADC1->SR, 0u, 0u, 3u); /* t_STAB: 3 us after ADON */
    ADC1->SR = 0u;
}

static void timebase_init(const stm32f4_clock_t *clk)
{
    /* TIM5: 32-bit free-running microsecond counter. */
    TIM5->CR1 = 0u;
    TIM5->PSC = clk->tim_apb1_Hz / 1000000u - 1u;
    TIM5->ARR = 0xFFFFFFFFu;
    TIM5->EGR = TIM_EGR_UG;
    TIM5->SR = 0u;
    TIM5->CR1 = TIM_CR1_CEN;
    s_time_hi = 0u;
    s_time_last = 0u;
    /* TIM2: 1 MHz, update (interrupt) every 1000 counts; URS: only overflows raise it. */
    TIM2->CR1 = TIM_CR1_URS;
    TIM2->PSC = clk->tim_apb1_Hz / 1000000u - 1u;
    TIM2->ARR = STM32F4_CONTROL_PERIOD_US - 1u;
    TIM2->EGR = TIM_EGR_UG;
    TIM2->SR = 0u;
    TIM2->DIER = TIM_DIER_UIE;
}

static int can_init(uint32_t btr)
{
    CAN1->MCR = (CAN1->MCR & ~CAN_MCR_SLEEP) | CAN_MCR_INRQ;
    if (!wait_flag_us(&CAN1->MSR, CAN_MSR_INAK | CAN_MSR_SLAK, CAN_MSR_INAK, 10000u)) {
        return 0;
    }
    CAN1->MCR = CAN_MCR_INRQ | CAN_MCR_ABOM | CAN_MCR_TXFP;
    CAN1->BTR = btr;
    /* Filter bank 0: 32-bit mask mode, mask 0 = accept everything into FIFO 0 (the protocol
     * layer counts unknown identifiers itself). */
    CAN1->FMR |= CAN_FMR_FINIT;
    CAN1->FA1R &= ~1u;
    CAN1->FS1R |= 1u;
    CAN1->FM1R &= ~1u;
    CAN1->FFA1R &= ~1u;
    CAN1->FB[0].FR1 = 0u;
    CAN1->FB[0].FR2 = 0u;
    CAN1->FA1R |= 1u;
    CAN1->FMR &= ~CAN_FMR_FINIT;
    CAN1->IER = CAN_IER_TMEIE | CAN_IER_FMPIE0;
    /* Leaving initialisation needs 11 recessive bits on the bus. */
    CAN1->MCR &= ~CAN_MCR_INRQ;
    if (!wait_flag_us(&CAN1->MSR, CAN_MSR_INAK, 0u, 10000u)) {
        return 0;
    }
    nvic_enable(IRQN_CAN1_TX, PRIO_CAN);
    nvic_enable(IRQN_CAN1_RX0, PRIO_CAN);
    return 1;
}

int stm32f4_hal_init(const stm32f4_hal_config_t *cfg)
{
    const stm32f4_clock_t *clk = stm32f4_clock_get();
    uint32_t btr;
    uint32_t half_us;
    if (cfg == NULL) {
        return TV_ERR_NULL;
    }
    s_pwm_arr = pwm_arr(clk->tim_apb2_Hz, cfg->pwm_frequency_Hz);
    btr = can_btr(clk->pclk1_Hz, cfg->can_bitrate_bps);
    if (s_pwm_arr == 0u || btr == 0u || clk->tim_apb1_Hz % 1000000u != 0u) {
        return TV_ERR_CONFIG;
    }
    s_status.clock_flags = clk->flags;
    s_status.reset_flags = clk->reset_flags;

    RCC->AHB1ENR |= RCC_AHB1ENR_GPIOAEN | RCC_AHB1ENR_GPIOBEN;
    RCC->APB1ENR |= RCC_APB1ENR_TIM2EN | RCC_APB1ENR_TIM5EN | RCC_APB1ENR_CAN1EN;
    RCC->APB2ENR |= RCC_APB2ENR_TIM1EN | RCC_APB2ENR_ADC1EN;
    (void)RCC->APB2ENR; /* the clock must be running before the first register access */
    /* While a debugger halts the core: TIM1 stops with its outputs disabled, TIM2 and the
     * watchdog freeze. */
    DBGMCU->APB1_FZ |= DBGMCU_APB1_FZ_DBG_TIM2_STOP | DBGMCU_APB1_FZ_DBG_IWDG_STOP;
    DBGMCU->APB2_FZ |= DBGMCU_APB2_FZ_DBG_TIM1_STOP;

    /* Bridge disabled before anything else drives it; the fault input pulled up. */
    GPIOB->BSRR = 1u << (BOARD_BRIDGE_EN_PIN + 16u);
    gpio_config(GPIOB, BOARD_BRIDGE_EN_PIN, GPIO_MODER_OUTPUT, 0u, 0u);
    gpio_config(GPIOB, BOARD_BRIDGE_FAULT_PIN, GPIO_MODER_INPUT, 0u, GPIO_PUPDR_PULLUP);

    timebase_init(clk);
    pwm_init();
    adc_init();

    /* Tick phase: TIM1 starts at 0 counting up, peaks after half a PWM period; TIM2 starts
     * so that its first overflow (and every later one, 1 ms being a whole number of PWM
     * periods) comes ADC_READY_US after a peak. */
    half_us = 500000u / cfg->pwm_frequency_Hz;
    s_tick_phase_us = STM32F4_CONTROL_PERIOD_US - (half_us + STM32F4_ADC_READY_US);

    gpio_config(GPIOB, BOARD_CAN_RX_PIN, GPIO_MODER_AF, BOARD_CAN_AF, GPIO_PUPDR_PULLUP);
    gpio_config(GPIOB, BOARD_CAN_TX_PIN, GPIO_MODER_AF, BOARD_CAN_AF, 0u);
    s_can_tx.n = 0u;
    s_can_rx.n = 0u;
    s_status.can_ok = (uint32_t)can_init(btr);

    CORE_DEMCR |= CORE_DEMCR_TRCENA;
    DWT_CYCCNT = 0u;
    DWT_CTRL |= DWT_CTRL_CYCCNTENA;
    s_initialised = 1u;
    return TV_OK;
}

int hal_init(void)
{
    stm32f4_hal_config_t cfg;
    stm32f4_hal_config_default(&cfg);
    return stm32f4_hal_init(&cfg);
}

void stm32f4_control_start(void)
{
    const uint32_t primask = stm32f4_irq_save();
    TIM1->CNT = 0u;
    TIM2->CNT = s_tick_phase_us;
    TIM2->SR = 0u;
    /* Back to back, same clock source: a fixed offset of a few bus cycles between the two. */
    TIM2->CR1 |= TIM_CR1_CEN;
    TIM1->CR1 |= TIM_CR1_CEN;
    nvic_enable(IRQN_TIM2, PRIO_CONTROL);
    stm32f4_irq_restore(primask);
}

void stm32f4_control_irq_begin(void)
{
    /* TIM2 counts microseconds from its overflow: its value now is the entry latency. */
    const uint32_t latency_us = TIM2->CNT;
    TIM2->SR = ~TIM_SR_UIF; /* rc_w0: clears UIF only; early, so it cannot re-trigger on exit */
    if (latency_us > s_status.tick_latency_max_us && latency_us < STM32F4_CONTROL_PERIOD_US) {
        s_status.tick_latency_max_us = latency_us;
    }
}

void stm32f4_control_irq_end(void)
{
    if ((TIM2->SR & TIM_SR_UIF) != 0u) {
        ++s_status.deadline_missed; /* the next period began while this tick ran */
    }
}

/* ---- watchdog, cycles, emergency stop ----------------------------------------------------- */

void stm32f4_watchdog_start(uint32_t timeout_ms)
{
    /* LSI 32 kHz / 32 (PR = 3) = 1 ms per count at the nominal frequency. */
    const uint32_t rl = timeout_ms < 1u ? 1u : (timeout_ms > 4095u ? 4095u : timeout_ms);
    IWDG->KR = IWDG_KEY_ENABLE; /* also starts the LSI */
    IWDG->KR = IWDG_KEY_WRITE_ACCESS;
    IWDG->PR = 3u;
    IWDG->RLR = rl;
    (void)wait_flag_us(&IWDG->SR, IWDG_SR_PVU | IWDG_SR_RVU, 0u, 1000u);
    IWDG->KR = IWDG_KEY_RELOAD;
}

void stm32f4_watchdog_kick(void)
{
    IWDG->KR = IWDG_KEY_RELOAD;
}

uint32_t stm32f4_cycles(void)
{
    return DWT_CYCCNT;
}

void stm32f4_emergency_stop(void)
{
    s_estop = 1u;
    TIM1->BDTR &= ~TIM_BDTR_MOE;
    GPIOB->BSRR = 1u << (BOARD_BRIDGE_EN_PIN + 16u);
}

/* Every fault and unexpected interrupt (startup.h): outputs safe, then wait for the watchdog. */
void startup_fault_hook(uint32_t exception_number)
{
    (void)exception_number;
    stm32f4_emergency_stop();
}

void stm32f4_status(stm32f4_status_t *st)
{
    uint32_t primask;
    if (st == NULL) {
        return;
    }
    primask = stm32f4_irq_save();
    s_status.can_bus_off = (CAN1->ESR & CAN_ESR_BOFF) != 0u ? 1u : 0u;
    *st = s_status;
    stm32f4_irq_restore(primask);
}

/* ---- hal.h: bridge -------------------------------------------------------------------------- */

int hal_pwm_set_duty(float duty)
{
    uint32_t ccr_fwd = s_pwm_arr + 1u; /* CCR > ARR: output inactive, 0 % */
    uint32_t ccr_rev = ccr_fwd;
    int rc = TV_OK;
    if (!s_initialised) {
        return TV_ERR_IO;
    }
    if (!(duty == duty) || duty - duty != 0.0f) {
        rc = TV_ERR_NONFINITE;
    } else if (duty > 1.0f || duty < -1.0f) {
        rc = TV_ERR_RANGE;
    }
    if (rc == TV_OK) {
        const float mag = duty < 0.0f ? -duty : duty;
        const uint32_t on = (uint32_t)(mag * (float)s_pwm_arr + 0.5f); /* active ticks per half period */
        if (on > 0u) {
            if (duty > 0.0f) {
                ccr_fwd = s_pwm_arr - on;
            } else {
                ccr_rev = s_pwm_arr - on;
            }
        }
    }
    /* Preloaded: both take effect together at the next update event. */
    TIM1->CCR1 = ccr_fwd;
    TIM1->CCR2 = ccr_rev;
    return rc;
}

int hal_bridge_enable(int enable)
{
    if (!s_initialised) {
        return TV_ERR_IO;
    }
    if (enable && s_estop) {
        return TV_ERR_FAULT;
    }
    GPIOB->BSRR = enable ? (1u << BOARD_BRIDGE_EN_PIN) : (1u << (BOARD_BRIDGE_EN_PIN + 16u));
    return TV_OK;
}

int hal_driver_fault(int *fault_active)
{
    if (fault_active == NULL) {
        return TV_ERR_NULL;
    }
    if (!s_initialised) {
        return TV_ERR_IO;
    }
    *fault_active = (GPIOB->IDR & (1u << BOARD_BRIDGE_FAULT_PIN)) == 0u ? 1 : 0;
    return TV_OK;
}

/* ---- hal.h: ADC and time ------------------------------------------------------------------ */

uint64_t hal_time_us(void)
{
    const uint32_t primask = stm32f4_irq_save();
    const uint32_t now = TIM5->CNT;
    uint64_t t;
    if (now < s_time_last) {
        ++s_time_hi;
    }
    s_time_last = now;
    t = ((uint64_t)s_time_hi << 32) | now;
    stm32f4_irq_restore(primask);
    return t;
}

int hal_adc_read(hal_adc_sample_t *sample)
{
    uint32_t attempt;
    if (sample == NULL) {
        return TV_ERR_NULL;
    }
    if (!s_initialised) {
        return TV_ERR_IO;
    }
    if ((ADC1->SR & ADC_SR_JEOC) == 0u) {
        ++s_status.adc_stale; /* no conversion since the last read: trigger or ADC stopped */
        return TV_ERR_IO;
    }
    for (attempt = 0u; attempt < 2u; ++attempt) {
        uint32_t k;
        ADC1->SR = ~(ADC_SR_JEOC | ADC_SR_JSTRT);
        for (k = 0u; k < HAL_ADC_CHANNELS; ++k) {
            sample->counts[k] = (uint16_t)(ADC1->JDR[k] & 0xFFFu);
        }
        if ((ADC1->SR & ADC_SR_JSTRT) == 0u) {
            break; /* no new group started while reading: one consistent set */
        }
        /* A group started during the read (only if the tick phase is off): wait for it. */
        (void)wait_flag_us(&ADC1->SR, ADC_SR_JEOC, ADC_SR_JEOC, 20u);
    }
    sample->t_us = hal_time_us();
    return TV_OK;
}

/* ---- hal.h: CAN ------------------------------------------------------------------------------ */

/* Move queued frames into free mailboxes. Called with CAN interrupts masked. */
static void can_tx_pump(void)
{
    while (s_can_tx.n > 0u && (CAN1->TSR & CAN_TSR_TME_Msk) != 0u) {
        const uint32_t mb = (CAN1->TSR >> CAN_TSR_CODE_Pos) & 3u;
        const hal_can_frame_t *f = &s_can_tx.f[s_can_tx.head];
        can_tx_mailbox_t *m = &CAN1->TX[mb];
        m->TIR = f->extended ? ((f->id << CAN_TIR_EXID_Pos) | CAN_TIR_IDE) : (f->id << CAN_TIR_STID_Pos);
        m->TDTR = f->dlc;
        m->TDLR = (uint32_t)f->data[0] | ((uint32_t)f->data[1] << 8) | ((uint32_t)f->data[2] << 16) |
                  ((uint32_t)f->data[3] << 24);
        m->TDHR = (uint32_t)f->data[4] | ((uint32_t)f->data[5] << 8) | ((uint32_t)f->data[6] << 16) |
                  ((uint32_t)f->data[7] << 24);
        m->TIR |= CAN_TIR_TXRQ;
        s_can_tx.head = (s_can_tx.head + 1u) % STM32F4_CAN_QUEUE_LEN;
        --s_can_tx.n;
    }
}

int hal_can_send(const hal_can_frame_t *frame)
{
    uint32_t primask;
    int rc = TV_OK;
    if (frame == NULL) {
        return TV_ERR_NULL;
    }
    if (frame->dlc > 8u || frame->id > (frame->extended ? 0x1FFFFFFFu : 0x7FFu)) {
        return TV_ERR_RANGE;
    }
    if (!s_status.can_ok) {
        return TV_ERR_IO;
    }
    primask = stm32f4_irq_save();
    if (s_can_tx.n < STM32F4_CAN_QUEUE_LEN) {
        s_can_tx.f[(s_can_tx.head + s_can_tx.n) % STM32F4_CAN_QUEUE_LEN] = *frame;
        ++s_can_tx.n;
        can_tx_pump();
    } else {
        ++s_status.can_tx_dropped;
        rc = TV_ERR_IO;
    }
    stm32f4_irq_restore(primask);
    return rc;
}

int hal_can_receive(hal_can_frame_t *frame)
{
    uint32_t primask;
    int got = 0;
    if (frame == NULL) {
        return TV_ERR_NULL;
    }
    if (!s_status.can_ok) {
        return TV_ERR_IO;
    }
    primask = stm32f4_irq_save();
    if (s_can_rx.n > 0u) {
        *frame = s_can_rx.f[s_can_rx.head];
        s_can_rx.head = (s_can_rx.head + 1u) % STM32F4_CAN_QUEUE_LEN;
        --s_can_rx.n;
        got = 1;
    }
    stm32f4_irq_restore(primask);
    return got;
}

/* A mailbox became empty: refill it from the queue. */
void CAN1_TX_IRQHandler(void);
void CAN1_TX_IRQHandler(void)
{
    const uint32_t primask = stm32f4_irq_save();
    /* Acknowledge the request-complete flags (rc_w1: RQCP0/1/2 at bits 0, 8, 16). */
    CAN1->TSR = (1u << 0) | (1u << 8) | (1u << 16);
    can_tx_pump();
    stm32f4_irq_restore(primask);
}

/* FIFO 0 holds frames: move them to the software queue. */
void CAN1_RX0_IRQHandler(void);
void CAN1_RX0_IRQHandler(void)
{
    const uint32_t primask = stm32f4_irq_save();
    if ((CAN1->RF0R & CAN_RF0R_FOVR0) != 0u) {
        CAN1->RF0R = CAN_RF0R_FOVR0; /* rc_w1 */
        ++s_status.can_rx_dropped;
    }
    while ((CAN1->RF0R & CAN_RF0R_FMP0_Msk) != 0u) {
        const can_fifo_mailbox_t *m = &CAN1->RX[0];
        const uint32_t rir = m->RIR;
        const uint32_t rdlr = m->RDLR;
        const uint32_t rdhr = m->RDHR;
        const uint32_t dlc = m->RDTR & 0xFu;
        if (s_can_rx.n < STM32F4_CAN_QUEUE_LEN) {
            hal_can_frame_t *f = &s_can_rx.f[(s_can_rx.head + s_can_rx.n) % STM32F4_CAN_QUEUE_LEN];
            uint32_t k;
            f->extended = (rir & CAN_TIR_IDE) != 0u ? 1u : 0u;
            f->id = f->extended ? (rir >> CAN_TIR_EXID_Pos) : (rir >> CAN_TIR_STID_Pos);
            f->dlc = (uint8_t)(dlc > 8u ? 8u : dlc);
            for (k = 0u; k < 8u; ++k) {
                const uint32_t word = k < 4u ? rdlr : rdhr;
                f->data[k] = (k < f->dlc && (rir & CAN_TIR_RTR) == 0u) ? (uint8_t)(word >> (8u * (k & 3u))) : 0u;
            }
            ++s_can_rx.n;
        } else {
            ++s_status.can_rx_dropped;
        }
        CAN1->RF0R = CAN_RF0R_RFOM0; /* release the FIFO output mailbox */
    }
    stm32f4_irq_restore(primask);
}
