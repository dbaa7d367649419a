/*
 * Basic class, 2026: SPIKE-RT on the hub. Wait for the force sensor, then trace the right edge of the line
 * from a 10 ms cyclic handler (app.cfg) until the run ends.
 */
#include "kernel_cfg.h"
#include "app.h"

#include <t_syslog.h>
#include <sil.h>
#include <syssvc/syslog.h>

#include <libcpp/libcpp.h>
#include <libcpp/spike/Clock.h>
#include <libcpp/spike/Display.h>
#include <libcpp/spike/Light.h>

#include "LineTracer.h"
#include "Starter.h"

using namespace spikeapi;

static Clock gClock;
static Light gLight;
static Display gDisplay;
static Starter gStarter(EPort::PORT_D);
static LineTracer gTracer(EPort::PORT_B, EPort::PORT_A, EPort::PORT_E);

void main_task(intptr_t unused)
{
  libcpp_sync();
  syslog_msk_log(LOG_UPTO(LOG_INFO), LOG_UPTO(LOG_EMERG));
  syslog(LOG_NOTICE, "basic_team_tracer: press the force sensor");
  gLight.turnOnColor(Light::EColor::ORANGE);
  gDisplay.showChar('R');

  while (!gStarter.isPushed()) {
    gClock.sleep(10 * 1000);
  }
  gLight.turnOnColor(Light::EColor::GREEN);
  gDisplay.off();
  syslog(LOG_NOTICE, "start at %lu ms", (unsigned long)(gClock.now() / 1000));
  gTracer.start();
  sta_cyc(TRACER_CYC);

  while (true) {
    gClock.sleep(1000 * 1000);
    syslog(LOG_INFO, "%ld mm at %lu s", (long)gTracer.distanceMm(), (unsigned long)(gClock.now() / 1000000));
  }
}

void tracer_task(intptr_t unused)
{
  gTracer.run();
  ext_tsk();
}
