/*
 * The ASP3 kernel services of the native mock (docs/NATIVE.md). The services below "Not provided" are
 * declared with ASP3's signatures on purpose: a program that calls one compiles, and the link fails with
 * "undefined reference to `wai_sem'", which names the missing service.
 */
#ifndef HAKO_KERNEL_H
#define HAKO_KERNEL_H

#include "t_stddef.h"

#define TMIN_TPRI 1
#define TMAX_TPRI 16
#define TMAX_ACTCNT 1U
#define TMAX_WUPCNT 1U

#define TSK_SELF 0
#define TSK_NONE 0

#define TA_ACT 0x01U /* CRE_TSK: activated when the kernel starts */
#define TA_STA 0x02U /* CRE_CYC, EV3_CRE_CYC: started when the kernel starts */

/* What a cyclic handler notifies (ASP3 CRE_CYC). */
#define TNFY_HANDLER 0x00U
#define TNFY_ACTTSK 0x03U
#define TNFY_WUPTSK 0x04U

#ifndef TOPPERS_MACRO_ONLY
#ifdef __cplusplus
extern "C" {
#endif

#ifdef __cplusplus
extern "C" {
#endif
ER act_tsk(ID tskid);
ER ext_tsk(void);
ER get_tid(ID *p_tskid);
ER slp_tsk(void);
ER tslp_tsk(TMO tmout);
ER wup_tsk(ID tskid);
ER dly_tsk(RELTIM dlytim);
ER get_tim(SYSTIM *p_systim);
ER sta_cyc(ID cycid);
ER stp_cyc(ID cycid);

ER ter_tsk(ID tskid);
ER get_pri(ID tskid, PRI *p_tskpri);
/* Not provided. */
ER chg_pri(ID tskid, PRI tskpri);
ER_UINT can_act(ID tskid);
ER_UINT can_wup(ID tskid);
ER rel_wai(ID tskid);
ER sus_tsk(ID tskid);
ER rsm_tsk(ID tskid);
ER rot_rdq(PRI tskpri);
ER loc_cpu(void);
ER unl_cpu(void);
ER dis_dsp(void);
ER ena_dsp(void);
ER sig_sem(ID semid);
ER wai_sem(ID semid);
ER pol_sem(ID semid);
ER twai_sem(ID semid, TMO tmout);
ER set_flg(ID flgid, FLGPTN setptn);
ER clr_flg(ID flgid, FLGPTN clrptn);
ER wai_flg(ID flgid, FLGPTN waiptn, MODE wfmode, FLGPTN *p_flgptn);
ER snd_dtq(ID dtqid, intptr_t data);
ER rcv_dtq(ID dtqid, intptr_t *p_data);
ER ext_ker(void);
#ifdef __cplusplus
}
#endif

#ifdef __cplusplus
}
#endif
#endif /* TOPPERS_MACRO_ONLY */
#endif /* HAKO_KERNEL_H */
