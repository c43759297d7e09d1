// articula/articula.h - the whole portable core in one include.
#ifndef ARTICULA_ARTICULA_H
#define ARTICULA_ARTICULA_H

#include "platform.h"
#include "transform.h"
#include "dh.h"
#include "actuation.h"
#include "ik_ypp.h"
#include "status.h"
#include "protocol.h"
#include "motion.h"
#include "servo.h"
#include "drive.h"

#endif  // ARTICULA_ARTICULA_H
