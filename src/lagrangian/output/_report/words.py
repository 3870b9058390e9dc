"""The report's words, in French (the course's vocabulary) and in English.

Every sentence of the report is a template here, with ``{name}`` slots filled by text or
by mathematics (`Math`), so that the builders hold no language at all.  The French is
the seed's: paramètres principaux, liaisons principales, champ de vitesses virtuelles
compatible, puissance virtuelle, composantes généralisées, intégrale première,
énergie cinétique T(Σ/R0), énergie potentielle U_P(Σ/R0).
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from .document import Run, Runs

__all__ = ["Words", "LANGUAGES"]

LANGUAGES = ("fr", "en")

_PHRASES: dict[str, tuple[str, str]] = {
    # -- titles ---------------------------------------------------------------------------------
    "title": ("Équations de Lagrange — {name}", "Lagrange's equations — {name}"),
    "system": ("Énoncé", "Statement"),
    "step1": ("1. Choix des liaisons principales", "1. Choice of the principal constraints"),
    "step2": ("2. Paramètres principaux", "2. Principal parameters (generalized coordinates)"),
    "step3": ("3. Champ de vitesses virtuelles compatible avec les liaisons principales",
              "3. Virtual velocity field compatible with the principal constraints"),
    "step4": ("4. Énergies cinétique et potentielle", "4. Kinetic and potential energies"),
    "step5": ("5. Composantes généralisées des efforts", "5. Generalized forces"),
    "step6": ("6. Équations de Lagrange", "6. Lagrange's equations"),
    "step7": ("7. Équations de liaison complémentaires", "7. Complementary constraint equations"),
    "integrals": ("Intégrales premières", "First integrals"),
    "check": ("Vérification par les théorèmes généraux (Remarque 4)",
              "Newton–Euler cross-check (Remark 4 of the course)"),
    "simulation": ("Simulation", "Simulation"),
    "matrix": ("Annexe : forme matricielle", "Appendix: matrix form"),
    # -- the system -------------------------------------------------------------------------------
    "galilean": ("{R0} est un repère galiléen.", "{R0} is a Galilean (inertial) frame."),
    "vertical up": ("{axis} est la verticale ascendante : la pesanteur est {g}.",
                    "{axis} is the ascending vertical: gravity is {g}."),
    "vertical down": ("{axis} est la verticale descendante : la pesanteur est {g}.",
                      "{axis} is the descending vertical (it points down): gravity is {g}."),
    "reference": ("Les équations sont écrites par rapport au repère {R}, qui n'est pas galiléen : aux efforts "
                  "donnés s'ajoutent les efforts d'inertie de Coriolis et d'entraînement (Remarque 3).",
                  "The equations are written relative to the frame {R}, which is not Galilean: the Coriolis "
                  "and transport inertial forces are added to the applied forces (Remark 3 of the course)."),
    "statement intro": ("On étudie le système (Σ) suivant : {what}.", "We study the following system (Σ): {what}."),
    "constituents": ("(Σ) est formé de :", "(Σ) is made of:"),
    "points given": ("Points nommés :", "Named points:"),
    "inertia principal given": ("moments principaux d'inertie en {P} dans la base {basis} : {values}",
                                "principal moments of inertia at {P} in the basis {basis}: {values}"),
    "inertia matrix given": ("matrice d'inertie en {P} dans la base {basis} : {matrix}",
                             "inertia matrix at {P} in the basis {basis}: {matrix}"),
    "loads given": ("Efforts donnés :", "Applied forces:"),
    "load item": ("« {name} » : {what}", "“{name}”: {what}"),
    "load gravity": ("pesanteur {g}", "gravity {g}"),
    "load on": ("pesanteur {g}, sur {on}", "gravity {g}, on {on}"),
    "load field": ("champ uniforme {g}, sur tous les éléments", "uniform field {g}, on every element"),
    "load field on": ("champ uniforme {g}, sur {on}", "uniform field {g}, on {on}"),
    "load force": ("force {F} appliquée en {P}", "force {F} applied at {P}"),
    "load torque": ("couple {C} exercé sur ({S})", "torque {C} exerted on ({S})"),
    "load torque reaction": ("couple {C} exercé sur ({S}) par ({S2})", "torque {C} exerted on ({S}) by ({S2})"),
    "load spring": ("ressort entre {A} et {B}, de raideur {k} et de longueur à vide {l0}",
                    "spring between {A} and {B}, of stiffness {k} and rest length {l0}"),
    "load damper": ("amortisseur entre {A} et {B}, de coefficient {c}",
                    "damper between {A} and {B}, of coefficient {c}"),
    "load potential": ("énergie potentielle {U}", "potential energy {U}"),
    "load generalized potential": ("potentiel généralisé {U}, qui dépend des vitesses",
                                   "generalized potential {U}, which depends on the rates"),
    "load dissipation": ("fonction de dissipation {D}", "dissipation function {D}"),
    "load joint damper": ("frottement visqueux entre ({S1}) et ({S2}), de coefficient {c}",
                          "viscous friction between ({S1}) and ({S2}), of coefficient {c}"),
    "load coulomb": ("frottement de Coulomb en {P}, de coefficient {f}",
                     "Coulomb friction at {P}, of coefficient {f}"),
    "load generalized": ("composantes généralisées données {Q}", "given generalized forces {Q}"),
    "constraints given": ("Liaisons :", "Constraints:"),
    "constraint item": ("{label} : {equation}", "{label}: {equation}"),
    "quoted": ("« {name} »", "“{name}”"),
    "body item": ("le solide ({S}) : masse {m}, centre d'inertie {G}, {OG}",
                  "the rigid body ({S}): mass {m}, centre of mass {G}, {OG}"),
    "body item no mass": ("le solide ({S}) : masse non donnée (son centre d'inertie {G} est fixe : elle n'entre pas "
                          "dans les équations de Lagrange), {OG}",
                          "the rigid body ({S}): mass not given (its centre of mass {G} is fixed: the mass does not "
                          "enter the Lagrange equations), {OG}"),
    "particle item": ("le point matériel {P} : masse {m}, {OP}", "the particle {P}: mass {m}, {OP}"),
    "parameters": ("Constantes du problème :", "Constants of the problem:"),
    "inputs": ("Entrées (commandes, fonctions du temps données) :", "Inputs (controls, given functions of time):"),
    "col symbol": ("symbole", "symbol"),
    "col name": ("nom", "name"),
    "col value": ("valeur", "value"),
    "col unit": ("unité", "unit"),
    "col description": ("description", "description"),
    "col initial": ("valeur initiale", "initial value"),
    "col rate": ("vitesse initiale", "initial rate"),
    # -- step 1 ---------------------------------------------------------------------------------
    "only constraint": ("La seule liaison est {c}.", "There is a single constraint: {c}."),
    "constraints": ("Les liaisons sont :", "The constraints are:"),
    "fixed point": ("la liaison « {X} point fixe » de ({S}) : {xyz}", "the fixed-point constraint at {X} of ({S}): {xyz}"),
    "pivot R0": ("la liaison pivot d'axe {axis} de ({S}) par rapport à {R0}",
                 "the hinge (revolute joint) of axis {axis} of ({S}) relative to {R0}"),
    "pivot": ("la liaison pivot d'axe {axis} entre ({S}) et ({S2})",
              "the hinge (revolute joint) of axis {axis} between ({S}) and ({S2})"),
    "ball joint": ("la liaison rotule de centre {X} entre ({S}) et {other}",
                   "the ball joint of centre {X} between ({S}) and {other}"),
    "rod": ("la liaison qui maintient {XP}{what}", "the constraint that keeps {XP}{what}"),
    "rod plane": ("la liaison qui maintient {XP}{what}, {P} restant dans le plan passant par {X} et normal à {n}",
                  "the constraint that keeps {XP}{what}, {P} staying in the plane through {X} normal to {n}"),
    "rod what": (" (tige de masse négligeable, fil tendu...)", " (a massless rod, a taut string...)"),
    "body plane": ("la liaison qui impose {cond} et ne laisse à ({S}) que {rot}",
                   "the constraint that imposes {cond} and leaves ({S}) only {rot}"),
    "rotations about": ("les rotations autour de {axes}", "the rotations about {axes}"),
    "rotation about": ("la rotation autour de {axes}", "the rotation about {axes}"),
    "perfect body plane": ("Elle est parfaite : ses actions se réduisent à une force selon {n} et à un couple "
                           "orthogonal aux rotations permises, dont la puissance virtuelle est nulle dans tout champ "
                           "compatible avec elle, puisque {cond} et que {rot}.",
                           "It is ideal (workless): its actions reduce to a force along {n} and a couple orthogonal "
                           "to the allowed rotations, whose virtual power is zero in every virtual field compatible "
                           "with it, since {cond} and {rot}."),
    "adherence": ("Ce n'est pas un contact sans frottement : le roulement sans glissement exige l'adhérence au "
                  "contact, composante tangentielle de l'action du support sur ({S}) ; c'est la réaction de la "
                  "liaison de roulement sans glissement en {I}, gardée comme liaison complémentaire (étape 7).",
                  "This is not a frictionless contact: rolling without slipping needs adherence at the contact, "
                  "the tangential part of the support's action on ({S}); it is the reaction of the rolling "
                  "constraint at {I}, kept as a complementary constraint (step 7)."),
    "not perfect": ("Elle n'est pas parfaite : son frottement ({why}) a une puissance virtuelle non nulle et figure "
                    "dans {Q} (étape 5) ; ses autres actions ont une puissance virtuelle nulle.",
                    "It is not ideal (not workless): its friction ({why}) has a nonzero virtual power and enters {Q} "
                    "(step 5); its other actions have zero virtual power."),
    "why coulomb": ("frottement de Coulomb « {name} » en {P}, opposé au glissement",
                    "Coulomb friction “{name}” at {P}, opposing the sliding"),
    "why damper": ("frottement visqueux « {name} » dans la liaison", "viscous friction “{name}” in the joint"),
    "line": ("la liaison glissière de {P} sur la droite {line}", "the slider of {P} along the line {line}"),
    "plane": ("la liaison de {P} avec le plan passant par {X} et normal à {n}",
              "the constraint keeping {P} in the plane through {X} normal to {n}"),
    "placement": ("la liaison qui place {E} en fonction des paramètres principaux",
                  "the constraint that places {E} as a function of the principal parameters"),
    "declared": ("{label} : {equation}", "{label}: {equation}"),
    "constraint number": ("la liaison {k}", "constraint {k}"),
    "multiplier table": ("Les multiplicateurs sont numérotés dans l'ordre des liaisons du modèle :",
                         "The multipliers are numbered in the order of the model's constraints:"),
    "col multiplier": ("multiplicateur", "multiplier"),
    "col constraint": ("liaison", "constraint"),
    "col row": ("équation", "equation"),
    "no slip": ("la liaison de roulement sans glissement de ({S}) en {I} : {equation}",
                "rolling without slipping of ({S}) at {I}: {equation}"),
    "coincide": ("la liaison qui maintient {P} en {Q} : {equation}", "the constraint that keeps {P} at {Q}: {equation}"),
    "equations count": ("{k} équations scalaires", "{k} scalar equations"),
    "equation count": ("1 équation scalaire", "1 scalar equation"),
    "holonomic": ("holonome", "holonomic"),
    "integrable": ("écrite sur les vitesses, elle s'intègre en {phi} : elle est donc holonome",
                   "written on the velocities, it integrates to {phi}: it is therefore holonomic"),
    "nonholonomic": ("non holonome (elle porte sur les vitesses)", "nonholonomic (a relation between velocities)"),
    "scleronomic": ("indépendante du temps", "time-independent"),
    "rheonomic": ("dépendante du temps", "time-dependent"),
    "principal": ("principale", "principal"),
    "principal declared": ("principale (le choix des paramètres la satisfait déjà)",
                           "principal (the choice of parameters already satisfies it)"),
    "complementary": ("complémentaire : elle est gardée comme équation (étape 7), avec le multiplicateur {lam}",
                      "complementary: it is kept as an equation (step 7), with the multiplier {lam}"),
    "complementary many": ("complémentaire : ses équations sont gardées (étape 7), avec les multiplicateurs {lam}",
                           "complementary: its equations are kept (step 7), with the multipliers {lam}"),
    "classified one": ("Elle est {a}, {b} et {c}.", "It is {a}, {b} and {c}."),
    "classified": ("{a}, {b}, {c}", "{a}, {b}, {c}"),
    "perfect fixed point": ("Elle est parfaite car la puissance virtuelle de la réaction {R} en {X} est nulle ; "
                            "en effet :", "It is ideal (workless) because the virtual power of the reaction {R} at {X} is zero:"),
    "because": ("car", "because"),
    "since": ("puisque", "since"),
    "and": ("et", "and"),
    "perfect pivot": ("Elle est parfaite (sans frottement, {MX}) : la puissance virtuelle des actions de liaison "
                      "est nulle,", "It is ideal (workless), being frictionless ({MX}): the virtual power of the constraint "
                      "actions is zero,"),
    "perfect joint": ("Elle est parfaite (sans frottement, {MX}) : les actions mutuelles de liaison, opposées, ont "
                      "une puissance virtuelle nulle, {X} étant commun aux deux solides,",
                      "It is ideal (workless), being frictionless ({MX}): the mutual constraint actions, equal and opposite, have zero total "
                      "virtual power, {X} being common to both bodies,"),
    "perfect ball": ("Elle est parfaite : les actions mutuelles de liaison se réduisent à une force en {X}, point "
                     "commun aux deux solides, de puissance virtuelle nulle.",
                     "It is ideal (workless): the mutual constraint actions reduce to a force at {X}, a point common to "
                     "both bodies, whose virtual power is zero."),
    "perfect rod": ("Elle est parfaite (sans frottement) : la réaction sur {P} n'a de composante que selon {dirs}, "
                    "{orth} à son champ de vitesses virtuelles puisque {XP2} est constant{plane} :",
                    "It is ideal (workless), being frictionless: the reaction on {P} only has components along {dirs}, "
                    "{orth} to its virtual velocity field since {XP2} is constant{plane}:"),
    "rod in plane": (" et que {P} reste dans le plan normal à {n}", " and {P} stays in the plane normal to {n}"),
    "orth one": ("direction orthogonale", "a direction orthogonal"),
    "orth many": ("directions orthogonales", "directions orthogonal"),
    "perfect smooth": ("Elle est parfaite (sans frottement) : la réaction est normale à {where}, qui contient "
                       "{V}.", "It is ideal (workless), being frictionless: the reaction is normal to {where}, which "
                       "contains {V}."),
    "the plane": ("ce plan", "that plane"),
    "the line": ("cette droite", "that line"),
    "perfect assumed": ("Elle est supposée parfaite : la puissance virtuelle de ses actions est nulle dans tout "
                        "champ de vitesses virtuelles compatible avec elle, et elles n'entrent dans aucune "
                        "composante généralisée.",
                        "It is assumed ideal (workless): the virtual power of its actions is zero in every virtual "
                        "velocity field compatible with it, and they enter no generalized force."),
    "perfect complementary": ("Elle est parfaite : sa réaction a une puissance virtuelle nulle dans tout champ "
                              "compatible avec elle, et ses composantes généralisées sont {Q}.",
                              "It is ideal (workless): its reaction has zero virtual power in every virtual field "
                              "compatible with it, and its generalized forces are {Q}."),
    "perfect no slip": ("Elle est parfaite car la puissance virtuelle de la réaction en {I} est nulle dans tout "
                        "champ compatible avec elle : {P}. Ses composantes généralisées sont {Q}.",
                        "It is ideal (workless) because the virtual power of the reaction at {I} is zero in every virtual "
                        "field compatible with it: {P}. Its generalized forces are {Q}."),
    "reaction is": ("La réaction exercée sur {E} est {R}.", "The reaction exerted on {E} is {R}."),
    "reaction on at": ("La réaction exercée sur ({S}) en {E} est {R}.", "The reaction exerted on ({S}) at {E} is {R}."),
    "adherence reaction": ("C'est la force d'adhérence au contact : le roulement sans glissement n'a lieu que tant "
                           "que le contact peut la fournir.",
                           "It is the adherence (static friction) force at the contact: rolling without slipping "
                           "lasts only as long as the contact can supply it."),
    "parameter count": ("Bilan des paramètres (6 par solide, 3 par point matériel, moins un par équation de liaison "
                        "principale) : {count}.",
                        "Parameter count (6 per rigid body and 3 per particle, minus one for each scalar equation of a "
                        "principal constraint): {count}."),
    "dof": ("Degrés de liberté : {count}, où n est le nombre de paramètres principaux, h celui des équations de "
            "liaison complémentaires holonomes et k celui des non holonomes.",
            "Degrees of freedom: {count}, where n is the number of principal parameters, h that of the holonomic "
            "complementary constraint equations and k that of the nonholonomic ones."),
    "dof holonomic": ("Degrés de liberté : {count}, où n est le nombre de paramètres principaux et h celui des "
                      "équations de liaison complémentaires.",
                      "Degrees of freedom: {count}, where n is the number of principal parameters and h that of the "
                      "complementary constraint equations."),
    "dof free": ("Degrés de liberté : {count} (les paramètres principaux sont indépendants).",
                 "Degrees of freedom: {count} (the principal parameters are independent)."),
    "dof nonholonomic": ("Les liaisons non holonomes ne restreignent que les vitesses : la position dépend de {p} "
                         "paramètres indépendants, la vitesse de {d} seulement.",
                         "The nonholonomic constraints restrict only the velocities: the position depends on {p} "
                         "independent parameters, the velocity on {d} only."),
    "planar": ("Le mouvement est plan par construction : toutes les vitesses sont parallèles au plan {plane}.",
               "The motion is planar by construction: every velocity is parallel to the plane {plane}."),
    "planar bodies": ("Le mouvement est plan par construction : toutes les vitesses sont parallèles au plan "
                      "{plane} et toutes les rotations se font autour de l'axe {axis}.",
                      "The motion is planar by construction: every velocity is parallel to the plane {plane} "
                      "and every rotation is about the axis {axis}."),
    "time dep note": ("(le temps y figure explicitement)", "(the time appears in it explicitly)"),
    # -- step 2 -----------------------------------------------------------------------------------
    "n params": ("On a donc {n} paramètres principaux : {list}.", "There are therefore {n} principal parameters: {list}."),
    "n params euler": ("On a donc {n} paramètres principaux qui sont les angles d'Euler {list} de ({S}).",
                       "There are therefore {n} principal parameters: the Euler angles {list} of ({S})."),
    "one param": ("On a donc un seul paramètre principal, {q}.", "There is therefore a single principal parameter: {q}."),
    "remark 1": ("Remarque 1 : il y a autant d'équations de Lagrange que de paramètres principaux, soit {n}.",
                 "Remark 1 (course): there are as many Lagrange equations as principal parameters, that is {n}."),
    "remark 1 lambda": ("Remarque 1 : il y a autant d'équations de Lagrange que de paramètres principaux, soit {n} ; "
                        "s'y ajoutent les {m} équations de liaison complémentaires (étape 7), pour les {m} "
                        "multiplicateurs.", "Remark 1 (course): there are as many Lagrange equations as principal "
                        "parameters, that is {n}; the {m} complementary constraint equations (step 7) are added, "
                        "for the {m} multipliers."),
    "remark 1 lambda one": ("Remarque 1 : il y a autant d'équations de Lagrange que de paramètres principaux, soit "
                            "{n} ; s'y ajoute l'équation de liaison complémentaire (étape 7), pour le multiplicateur.",
                            "Remark 1 (course): there are as many Lagrange equations as principal parameters, that is {n}; "
                            "the complementary constraint equation (step 7) is added, for the multiplier."),
    # -- step 3 -----------------------------------------------------------------------------------
    "frames": ("Repères et rotations :", "Frames and rotations:"),
    "fixed": ("fixe", "fixed"),
    "attached": ("lié à", "attached to"),
    "principal frame": ("{F} est un repère principal d'inertie de ({S}) ; la matrice principale d'inertie en {P} "
                        "de ({S}){huygens} est", "{F} is a principal frame of inertia of ({S}); the principal "
                        "inertia matrix of ({S}) at {P}{huygens} is"),
    "inertia frame": ("La matrice d'inertie en {P} de ({S}), dans la base {basis} de {F}{huygens}, est",
                      "The inertia matrix of ({S}) at {P}, in the basis {basis} of {F}{huygens}, is"),
    "huygens": (", transportée de {A} en {P} par le théorème de Huygens,",
                ", moved from {A} to {P} by the parallel-axis theorem,"),
    "angular velocities": ("Vecteurs rotation :", "Angular velocities:"),
    "virtual field": ("Le champ de vitesses virtuelles compatible avec les liaisons principales est {field} ; aux "
                      "points où s'appliquent les efforts donnés :", "The virtual velocity field compatible with "
                      "the principal constraints is {field}; at the points where the applied forces act:"),
    "virtual torsor": ("Le champ des vitesses virtuelles de chaque solide (S) est un torseur, le torseur cinématique "
                       "virtuel, donné par ses éléments de réduction en un point {A} de (S), tel que {field} :",
                       "The virtual velocity field of each rigid body (S) is a screw (the virtual kinematic screw, or "
                       "twist), given by its reduction elements at a point {A} of (S), such that {field}:"),
    "comoment intro": ("Les liaisons principales parfaites ne travaillent pas dans ce champ : la puissance virtuelle "
                       "des actions d'une liaison est le comoment du torseur de ses actions {torsor}, réduit en un "
                       "point X, et du torseur cinématique virtuel : {P}.",
                       "The ideal (workless) principal constraints do no work in this field: the virtual power of a "
                       "constraint's actions is the comoment of their screw {torsor}, reduced at a point X, with the "
                       "virtual kinematic screw: {P}."),
    "comoment short": ("Comoments des liaisons principales", "Comoments of the principal constraints"),
    "comoment fixed point": ("Liaison « {X} point fixe » de ({S}) : rotule parfaite en {X}, de moment nul en {X} ;",
                             "Fixed point {X} of ({S}): an ideal ball joint at {X}, of zero moment about {X};"),
    "comoment ball": ("Liaison rotule de centre {X} entre ({S}) et {S1} : parfaite, de moment nul en {X} ;",
                      "Ball joint of centre {X} between ({S}) and {S1}: ideal, of zero moment about {X};"),
    "comoment pivot": ("Liaison pivot en {X} de ({S}) par rapport à {S1} : parfaite, son moment en {X} est "
                       "orthogonal à l'axe ; dans le mouvement relatif, {X} est fixe et la rotation a lieu autour "
                       "de l'axe :",
                       "Hinge at {X} of ({S}) relative to {S1}: ideal, its moment about {X} is orthogonal to the "
                       "axis; in the relative motion, {X} is fixed and the rotation is about the axis:"),
    "comoment rod": ("Liaison de {P} (point matériel, torseur cinématique réduit à sa vitesse) : sans frottement, la "
                     "réaction n'a de composante que selon {dirs} ;",
                     "Constraint on {P} (a particle, whose kinematic screw reduces to its velocity): frictionless, "
                     "the reaction only has components along {dirs};"),
    "comoment plane": ("Liaison de {P} avec le plan, sans frottement : la réaction est portée par {dirs} ;",
                       "Frictionless constraint of {P} to the plane: the reaction is along {dirs};"),
    "comoment line": ("Glissière de {P} sans frottement : la réaction est orthogonale à {dirs} ;",
                      "Frictionless slider of {P}: the reaction is orthogonal to {dirs};"),
    "comoment body plane": ("Liaison de ({S}) avec son support : ses actions, réduites en {G}, sont une force selon {n} "
                            "et un moment orthogonal à {turns} ;",
                            "Constraint of ({S}) on its support: its actions, reduced at {G}, are a force along {n} "
                            "and a moment orthogonal to {turns};"),
    "inertia operator": ("où {Pi} est l'opérateur d'inertie de ({S}) en {P} : {op} (moment cinétique en {P}) ; sa "
                         "matrice dans la base {basis} est donnée à l'étape 3.",
                         "where {Pi} is the inertia operator (inertia tensor) of ({S}) at {P}: {op} (the angular momentum "
                         "about {P}); its matrix in the basis {basis} is given at step 3."),
    "virtual torsor short": ("Torseurs cinématiques virtuels", "Virtual kinematic screws"),
    # -- step 4 -----------------------------------------------------------------------------------
    "energies": ("Les énergies cinétique et potentielle compatibles de (Σ) par rapport à {R} sont :",
                 "The kinetic and potential energies of (Σ) relative to {R} are:"),
    "koenig": ("(théorème de König)", "(König's theorem)"),
    "no potential": ("Aucun effort donné ne dérive d'une énergie potentielle : {U}.",
                     "No applied force derives from a potential energy: {U}."),
    "potential of": ("Énergie potentielle de chaque effort conservatif :", "Potential energy of each conservative force:"),
    "cste": ("cste", "const"),
    # -- step 5 -----------------------------------------------------------------------------------
    "virtual power intro": ("La puissance virtuelle de chaque effort donné, dans le champ de vitesses virtuelles "
                            "compatible, s'écrit {P}, dont les coefficients sont les composantes généralisées {Q} :",
                            "The virtual power of each applied force in the compatible virtual velocity field is "
                            "{P}; its coefficients are the generalized forces {Q}:"),
    "zero because": ("{Q} car {why}", "{Q} because {why}"),
    "point still": ("{P} ne bouge pas quand {q} varie : {d}", "{P} does not move when {q} varies: {d}"),
    "points still": ("{P} ne bougent pas quand {q} varie : {d}", "{P} do not move when {q} varies: {d}"),
    "orthogonal": ("la force est orthogonale à {d}", "the force is orthogonal to {d}"),
    "no rotation": ("{S} ne tourne pas quand {q} varie", "{S} does not turn when {q} varies"),
    "couple orthogonal": ("le couple est orthogonal à {d}", "the couple is orthogonal to {d}"),
    "length still": ("la longueur {AB} ne dépend pas de {q}", "the length {AB} does not depend on {q}"),
    "U still": ("{U} ne dépend pas de {q}", "{U} does not depend on {q}"),
    "not given": ("aucune composante n'est donnée sur {q}", "no component is given on {q}"),
    "cancel": ("les contributions se compensent", "the contributions cancel"),
    "derives": ("« {name} » dérive d'une énergie potentielle : {Q} pour tout {i} (vérifié) ; il est pris en compte "
                "par {UP} à l'étape 6.", "“{name}” derives from a potential energy: {Q} for every {i} (checked); "
                "it enters through {UP} in step 6."),
    "derives constant": ("« {name} » est constant ({why}) : il dérive d'une énergie potentielle, {Q} pour tout {i} "
                         "(vérifié) ; il est pris en compte par {UP} à l'étape 6.",
                         "“{name}” is constant ({why}): it derives from a potential energy, {Q} for every {i} "
                         "(checked); it enters through {UP} in step 6."),
    "constant because": ("{names} {verb} une constante du problème", "{names} {verb} a constant of the problem"),
    "is one": ("est", "is"),
    "are one": ("sont chacun", "are each"),
    "driven": ("« {name} » est commandé par {u}, {what} : il ne dérive pas d'une énergie potentielle ({why}) ; ses "
               "composantes généralisées figurent dans {Q}.",
               "“{name}” is driven by {u}, {what}: it does not derive from a potential energy ({why}); its "
               "generalized forces enter {Q}."),
    "driven one": ("une entrée, fonction du temps donnée", "an input, a given function of time"),
    "driven many": ("des entrées, fonctions du temps données", "inputs, given functions of time"),
    "driven why": ("{U} n'en serait une que pour une entrée {u} constante", "{U} would be one only for a constant input {u}"),
    "not conservative": ("« {name} » ne dérive pas d'une énergie potentielle : ses composantes généralisées "
                         "figurent dans {Q}.", "“{name}” does not derive from a potential energy: its generalized "
                         "forces enter {Q}."),
    "load title": ("« {name} » ({kind}{extra}) :", "“{name}” ({kind}{extra}):"),
    "kind gravity": ("pesanteur", "gravity"),
    "kind field": ("champ uniforme", "uniform field"),
    "kind pointforce": ("force", "force"),
    "kind torque": ("couple", "couple"),
    "kind spring": ("ressort", "spring"),
    "kind damper": ("amortisseur visqueux", "viscous damper"),
    "kind potential": ("énergie potentielle donnée", "given potential energy"),
    "kind generalized potential": ("potentiel généralisé donné, dépendant des vitesses",
                                   "given generalized potential, depending on the rates"),
    "generalized potential": ("« {name} » dérive d'un potentiel généralisé {U}, qui dépend des vitesses : ses "
                              "composantes sont {Q} (et non {Q0}, qui en oublierait le premier terme). Ce n'est pas "
                              "une énergie potentielle {UP} : ses composantes figurent dans {Qnc}. La partie de "
                              "{U} linéaire en les vitesses est gyroscopique : elle ne travaille pas lorsque ses "
                              "coefficients ne dépendent pas de t.",
                              "“{name}” derives from a generalized potential {U}, which depends on the rates: its "
                              "components are {Q} (not {Q0}, which would drop the first term). It is not a potential "
                              "energy {UP}: its components enter {Qnc}. The part of {U} linear in the rates is "
                              "gyroscopic: it does no work when its coefficients do not depend on t."),
    "kind generalizedforce": ("composantes généralisées données", "given generalized forces"),
    "kind dissipation": ("fonction de dissipation de Rayleigh", "Rayleigh dissipation function"),
    "kind jointdamper": ("frottement visqueux dans une liaison", "viscous friction in a joint"),
    "kind coulombfriction": ("frottement de Coulomb", "Coulomb friction"),
    "kind inertial: Coriolis": ("effort d'inertie de Coriolis", "Coriolis inertial force"),
    "kind inertial: entrainment": ("effort d'inertie d'entraînement", "transport inertial force"),
    "perfect no Q": ("Les liaisons principales étant parfaites, la puissance virtuelle de leurs efforts est nulle : "
                     "ils n'apparaissent dans aucune composante généralisée.",
                     "Since the principal constraints are ideal (workless), the virtual power of their forces is zero: "
                     "they appear in no generalized force."),
    "complementary Q": ("Les réactions des liaisons complémentaires ont pour composantes généralisées {Q} (étape "
                        "7), où {lam} est le multiplicateur de la liaison complémentaire k et {a} le coefficient de "
                        "la vitesse {qd} dans son équation ({f} pour une liaison holonome {fk}).",
                        "The reactions of the complementary constraints have the generalized forces {Q} (step 7), "
                        "where {lam} is the multiplier of complementary constraint k and {a} the coefficient of "
                        "the rate {qd} in its equation ({f} for a holonomic constraint {fk})."),
    "complementary Q one": ("La réaction de la liaison complémentaire a pour composantes généralisées {Q} (étape 7), "
                            "où {lam} est son multiplicateur et {a} le coefficient de la vitesse {qd} dans son "
                            "équation ({f} pour une liaison holonome {fk}).",
                            "The reaction of the complementary constraint has the generalized forces {Q} (step 7), "
                            "where {lam} is its multiplier and {a} the coefficient of the rate {qd} in its equation "
                            "({f} for a holonomic constraint {fk})."),
    "perfect no Q but": ("Les autres liaisons principales étant parfaites, la puissance virtuelle de leurs efforts "
                         "est nulle. Dans les liaisons qui ne le sont pas, seuls les frottements travaillent : ils "
                         "figurent ci-dessus parmi les efforts non conservatifs, et les autres actions de ces "
                         "liaisons ont une puissance virtuelle nulle.",
                         "The other principal constraints being ideal (workless), the virtual power of their forces "
                         "is zero. In the constraints that are not, only the friction works: it is among the "
                         "non-conservative forces above, and the other actions of those constraints have zero "
                         "virtual power."),
    "perfect no Q none": ("Aucune liaison principale n'est parfaite, mais dans chacune seul le frottement ({names}) "
                          "travaille : il figure ci-dessus parmi les efforts non conservatifs, et les autres actions "
                          "de ces liaisons ont une puissance virtuelle nulle.",
                          "No principal constraint is ideal, but in each only the friction ({names}) works: it is "
                          "among the non-conservative forces above, and the other actions of those constraints "
                          "have zero virtual power."),
    "perfect no Q none one": ("La liaison principale n'est pas parfaite, mais seul son frottement ({names}) travaille : "
                              "il figure ci-dessus parmi les efforts non conservatifs, et les autres actions de la "
                              "liaison ont une puissance virtuelle nulle.",
                              "The principal constraint is not ideal, but only its friction ({names}) works: it is "
                              "among the non-conservative forces above, and the other actions of the constraint "
                              "have zero virtual power."),
    "multiplier def": ("{sum} : les composantes généralisées des réactions des liaisons complémentaires (étape 5).",
                       "{sum}: the generalized forces of the complementary constraints' reactions (step 5)."),
    "multiplier def one": ("{sum} : les composantes généralisées de la réaction de la liaison complémentaire (étape 5).",
                           "{sum}: the generalized forces of the complementary constraint's reaction (step 5)."),
    "nc total": ("Composantes généralisées des efforts non conservatifs :", "Generalized forces of the "
                 "non-conservative forces:"),
    "no loads": ("Aucun effort donné.", "No applied force."),
    # -- step 6 -----------------------------------------------------------------------------------
    "lagrange n": ("Les {n} équations de Lagrange sont :", "The {n} Lagrange equations are:"),
    "lagrange one": ("L'équation de Lagrange est :", "The Lagrange equation is:"),
    "et": ("et", "and"),
    "constant": ("constante", "constant"),
    "first integral K": ("intégrale première du mouvement, dans laquelle {K}.",
                         "a first integral of the motion, in which {K}."),
    "with values": ("{value} avec les valeurs initiales du modèle", "{value} with the model's initial values"),
    "using integrals": ("ou encore, en tenant compte de {eqs} :", "or, using {eqs}:"),
    "conservative": ("Le système (Σ) est conservatif par rapport à {R} (Remarque 2) : tous les efforts donnés "
                     "dérivent d'une énergie potentielle et toutes les liaisons sont parfaites et principales. Avec "
                     "le lagrangien {L}, les équations s'écrivent", "The system (Σ) is conservative relative to "
                     "{R} (Remark 2 of the course): every applied force derives from a potential energy and every constraint "
                     "is ideal (workless) and principal. With the Lagrangian {L}, the equations read"),

    "conservative constrained": ("Le système (Σ) est conservatif par rapport à {R} : tous les efforts donnés "
                                 "dérivent d'une énergie potentielle et toutes les liaisons sont parfaites, principales "
                                 "ou complémentaires indépendantes du temps — la réaction {sum} de ces dernières ne "
                                 "travaille pas au cours du mouvement. Avec le lagrangien {L}, les équations s'écrivent "
                                 "(Remarque 2, avec les multiplicateurs)",
                                 "The system (Σ) is conservative relative to {R}: every applied force derives from a "
                                 "potential energy and every constraint is ideal (workless), principal or complementary and "
                                 "time-independent — the reaction {sum} of the latter does no work along the motion. "
                                 "With the Lagrangian {L}, the equations read (Remark 2, with the multipliers)"),
    "entrainment terms": ("où {gamma} est l'accélération par rapport à {R0} de l'origine {O} de {R}, {G} le centre "
                          "d'inertie{many}, {Omega} la rotation de {R} par rapport à {R0} et {Pi} l'opérateur "
                          "d'inertie de (Σ) en {O} (Remarque 3).",
                          "where {gamma} is the acceleration relative to {R0} of the origin {O} of {R}, {G} the "
                          "centre of mass{many}, {Omega} the rotation of {R} relative to {R0} and {Pi} the inertia "
                          "operator of (Σ) at {O}."),
    "entrainment potential fixed": ("Cette énergie potentielle existe parce que la rotation {Omega} est constante, {rate} : le terme "
                                    "{term} de l'accélération d'entraînement, qui ne dérive d'aucune énergie "
                                    "potentielle, est nul ; l'origine {O} étant fixe dans {R0}, {gamma}, il ne reste "
                                    "que la force centrifuge.",
                                    "This potential energy exists because the rotation {Omega} is constant, {rate}: the term {term} of the "
                                    "transport acceleration, which derives from no potential energy, vanishes; the "
                                    "origin {O} being fixed in {R0}, {gamma}, only the centrifugal force is left."),
    "entrainment potential moving": ("Cette énergie potentielle existe parce que la rotation {Omega} est constante, {rate} : le terme {term} de "
                                     "l'accélération d'entraînement, qui ne dérive d'aucune énergie potentielle, est "
                                     "nul ; l'accélération {gamma} de l'origine {O}, uniforme, donne le terme en "
                                     "{gamma}, qui dépend du temps.",
                                     "This potential energy exists because the rotation {Omega} is constant, {rate}: the term {term} of the "
                                     "transport acceleration, which derives from no potential energy, vanishes; the "
                                     "acceleration {gamma} of the origin {O}, uniform, gives the term in {gamma}, which "
                                     "depends on the time."),
    "each element": (" de chaque élément, de masse m", " of each element, of mass m"),
    "coulomb exact": ("C'est la loi exacte (sans régularisation), valable en glissement, {v}, où N est la composante "
                      "normale de l'action du support (étape 7) ; quand le glissement cesse, {v0}, la simulation "
                      "passe à l'adhérence tant que {stick}.",
                      "This is the exact law (no regularization), valid while sliding, {v}, where N is the normal "
                      "component of the support's action (step 7); when the sliding stops, {v0}, the simulation "
                      "switches to sticking as long as {stick}."),
    "conservative timed": ("Les liaisons dépendant du temps, {L} dépend explicitement de {t} ({dL}) : les équations "
                           "gardent cette forme, mais l'énergie n'est pas une intégrale première.",
                           "The constraints depending on the time, {L} depends on {t} explicitly ({dL}): the "
                           "equations keep this form, but the energy is not a first integral."),
    "not conservative system": ("Le système n'est pas conservatif : {names} ne dérive pas d'une énergie "
                                "potentielle.", "The system is not conservative: {names} does not derive from a "
                                "potential energy."),
    "not conservative systems": ("Le système n'est pas conservatif : {names} ne dérivent pas d'une énergie "
                                 "potentielle.", "The system is not conservative: {names} do not derive from a "
                                 "potential energy."),
    "with multipliers": ("Les liaisons complémentaires ajoutent {sum} au second membre (étape 7).",
                         "The complementary constraints add {sum} to the right-hand side (step 7)."),
    "with multiplier": ("La liaison complémentaire ajoute {sum} au second membre (étape 7).",
                        "The complementary constraint adds {sum} to the right-hand side (step 7)."),
    # -- step 7 -----------------------------------------------------------------------------------
    "pin reaction": ("La réaction {R} en {O}, qui n'entre pas dans les équations de Lagrange (la liaison est parfaite), "
                     "se déduit ensuite du théorème de la résultante dynamique appliqué à {S} :",
                     "The reaction {R} at {O}, which does not enter Lagrange's equations (the constraint is ideal), "
                     "then follows from the resultant theorem applied to {S}:"),
    "no complementary": ("Toutes les liaisons ont été prises principales : il n'y a pas d'équation de liaison "
                         "complémentaire, et les {n} équations de Lagrange déterminent le mouvement.",
                         "All constraints were taken as principal: there is no complementary constraint equation, "
                         "and the {n} Lagrange equations determine the motion."),
    "no complementary one": ("Toutes les liaisons ont été prises principales : il n'y a pas d'équation de liaison "
                             "complémentaire, et l'équation de Lagrange détermine le mouvement.",
                             "All constraints were taken as principal: there is no complementary constraint "
                             "equation, and the Lagrange equation determines the motion."),
    "complementary rows": ("Les équations de liaison complémentaires complètent le système ; avec les {n} équations "
                           "de Lagrange, elles déterminent les {n} paramètres et les {m} multiplicateurs {lams} :",
                           "The complementary constraint equations complete the system; with the {n} Lagrange "
                           "equations they determine the {n} parameters and the {m} multipliers {lams}:"),
    "complementary row": ("L'équation de liaison complémentaire complète le système ; avec les {n} équations de "
                          "Lagrange, elle détermine les {n} paramètres et le multiplicateur {lams} :",
                          "The complementary constraint equation completes the system; with the {n} Lagrange "
                          "equations it determines the {n} parameters and the multiplier {lams}:"),
    "reaction of at": ("Réaction {R} de la liaison « {name} » sur ({S}) en {E} :",
                       "Reaction {R} of the constraint “{name}” on ({S}) at {E}:"),
    "reaction of": ("Réaction {R} de la liaison « {name} » sur {E} :", "Reaction {R} of the constraint “{name}” on {E}:"),
    "signs used": ("Les hypothèses déclarées ({declared}) donnent {facts} : les valeurs absolues, racines de carrés "
                   "et signes de ces expressions se simplifient dans les efforts ci-dessous.",
                   "The declared assumptions ({declared}) give {facts}: the absolute values, square roots of squares "
                   "and signs of these expressions simplify in the efforts below."),
    "sign general": ("pour toutes les valeurs permises", "for every allowed value"),
    "sign at values": ("aux valeurs déclarées des paramètres", "at the declared values of the parameters"),
    "rows chosen frame": ("Écrite dans {declared}, la liaison « {name} » donne {k} équations de rang {r} seulement ; "
                          "le même vecteur est écrit dans la base de {frame}, où {r} composantes seulement ne sont "
                          "pas identiquement nulles : {kept}.",
                          "Written in {declared}, the constraint “{name}” gives {k} rows of rank {r} only; the same "
                          "vector is written along the axes of {frame}, where only {r} of its components are not "
                          "identically zero: {kept}."),
    "rows chosen subset": ("Écrite dans {declared}, la liaison « {name} » donne {k} équations de rang {r} seulement ; "
                           "on garde les composantes selon {kept}, indépendantes (QR à pivot en un état générique), les autres en étant "
                           "des combinaisons.",
                           "Written in {declared}, the constraint “{name}” gives {k} rows of rank {r} only; the "
                           "components along {kept} are kept, independent (pivoted QR at a generic state), the others being combinations "
                           "of them."),
    "multipliers are": ("En éliminant les accélérations entre les équations de Lagrange et les équations de liaison "
                        "dérivées par rapport au temps (deux fois pour une liaison holonome), les multiplicateurs "
                        "valent :",
                        "Eliminating the accelerations between the Lagrange equations and the constraint equations "
                        "differentiated with respect to time (twice for a holonomic one), the multipliers are:"),
    "tension": ("Tension de la liaison (positive quand elle tire {P} vers {X}) :",
                "Tension of the constraint (positive when it pulls {P} towards {X}):"),
    "tension angle": ("soit, en posant {sub} ({theta} angle de {XP} avec la verticale descendante, opposée à {e}) :",
                      "that is, with {sub} ({theta} the angle of {XP} from the descending vertical, opposite to "
                      "{e}):"),
    "normal force": ("La composante normale N de l'action du support sur {P}, qui ne travaille pas et n'entre donc "
                     "pas dans les équations de Lagrange, s'obtient en projetant le théorème de la résultante "
                     "dynamique appliqué à {P} sur la normale {n} au contact (la force de frottement {name} lui est "
                     "orthogonale) :",
                     "The normal component N of the support's action on {P}, which does no work and so does not "
                     "enter Lagrange's equations, follows from the resultant theorem applied to {P}, projected on "
                     "the contact's normal {n} (the friction force {name} is orthogonal to it):"),
    "normal agrees": ("C'est la valeur {N} que la loi de frottement du modèle utilise.",
                      "This is the value {N} that the model's friction law uses."),
    "normal differs": ("La loi de frottement du modèle utilise {N}, qui n'est pas cette valeur : elle ne décrit ce "
                       "contact que si le modèle le justifie autrement.",
                       "The model's friction law uses {N}, which is not this value: it describes this contact only "
                       "if the model justifies it otherwise."),
    "stick": ("À l'arrêt ({rest}), {q} donne la force tangentielle que le contact doit fournir, {Rt} selon {e} ; "
              "le contact adhère tant qu'elle reste dans le cône de frottement, {cone}, soit :",
              "At rest ({rest}), {q} gives the tangential force the contact must supply, {Rt} along {e}; the "
              "contact sticks as long as it stays within the friction cone, {cone}, that is:"),
    "stick holds": ("Avec les valeurs du modèle, {value} ≤ {limit} : une fois arrêté, {P} reste immobile.",
                    "With the model's values, {value} ≤ {limit}: once stopped, {P} stays at rest."),
    "stick fails": ("Avec les valeurs du modèle, {value} > {limit} : {P} ne peut rester immobile et repart.",
                    "With the model's values, {value} > {limit}: {P} cannot stay at rest and slides again."),
    "multiplier is": ("En éliminant les accélérations entre les équations de Lagrange et l'équation de liaison "
                      "dérivée {times} par rapport au temps, le multiplicateur vaut :",
                      "Eliminating the accelerations between the Lagrange equations and the constraint equation "
                      "differentiated {times} with respect to time, the multiplier is:"),
    # -- integrals --------------------------------------------------------------------------------
    "cyclic": ("{q} est un paramètre cyclique : {why}, donc {eq} s'intègre :", "{q} is cyclic: {why}, so {eq} "
               "integrates:"),
    "no row": ("{qd} ne figure dans aucune équation de liaison complémentaire ({a})",
               "{qd} appears in no complementary constraint equation ({a})"),
    "momentum": ("{why}, donc {eq} s'intègre :", "{why}, so {eq} integrates:"),
    "inputs off": ("Les entrées coupées ({zero}), ", "With the inputs off ({zero}), "),
    "energy integral": ("{L} ne dépend pas explicitement du temps et {cond} ; {T} étant une forme quadratique "
                        "homogène des vitesses, l'intégrale première de l'énergie s'écrit :",
                        "{L} does not depend explicitly on time and {cond}; since {T} is a homogeneous "
                        "quadratic form in the rates, the energy integral reads:"),
    "jacobi integral": ("{L} ne dépend pas explicitement du temps et {cond}. Écrivons {parts}, où {T210} "
                        "sont les parties de {T} de degré 2, 1 et 0 par rapport aux vitesses {qd} : {T1} ou {T0} "
                        "n'étant pas nul, {E} n'est pas conservée, mais l'intégrale première de Painlevé–Jacobi "
                        "l'est :", "{L} does not depend explicitly on time and {cond}. Write {parts}, where "
                        "{T210} are the parts of {T} of degree 2, 1 and 0 in the rates {qd}: {T1} or {T0} "
                        "not being zero, {E} is not conserved, but the Painlevé–Jacobi integral is:"),
    "constant speed": ("Les équations réduites, où les vitesses dépendantes sont éliminées par les liaisons non "
                       "holonomes, donnent {d} : {qd} est une intégrale première.",
                       "The reduced equations, where the dependent rates are eliminated by the nonholonomic "
                       "constraints, give {d}: {qd} is a first integral."),
    "symmetry integral": ("Le système étant invariant par une symétrie de ses efforts et de ses liaisons (théorème de "
                          "Noether), la quantité suivante est une intégrale première :",
                          "The system being invariant under a symmetry of its forces and constraints (Noether's "
                          "theorem), the following quantity is a first integral:"),
    "jacobi moving": ("{L} ne dépend pas explicitement du temps et {cond}. Les équations étant écrites dans le "
                      "repère {R}, entraîné par rapport à {R0} par un mouvement imposé, {T2} est une forme quadratique "
                      "homogène des vitesses et {U} contient l'énergie potentielle des efforts d'inertie "
                      "d'entraînement (Remarque 3) : l'intégrale première est celle de Painlevé–Jacobi, et non "
                      "l'énergie mécanique {E} dans le repère galiléen, que le mouvement imposé fait varier :",
                      "{L} does not depend explicitly on time and {cond}. Since the equations are written in the "
                      "frame {R}, which moves relative to {R0} with a prescribed motion, {T2} is a homogeneous "
                      "quadratic form in the rates and {U} holds the potential energy of the transport inertial forces "
                      "(Remark 3 of the course): the first integral is the Painlevé–Jacobi one, not the mechanical "
                      "energy {E} in the Galilean frame, which the prescribed motion changes:"),
    "at t0": ("à", "at"),
    "prescribed": ("mouvement imposé", "prescribed motion"),
    "reaction": ("réaction", "reaction"),
    "balance": ("L'énergie {E} n'est donc pas conservée ; le théorème de l'énergie cinétique donne sa variation, "
                "terme par terme :", "The energy {E} is therefore not conserved; the work–energy theorem gives "
                "its rate, term by term:"),
    "balance timed": ("Avec {T} (parties de degré 2, 1 et 0 en q̇) et {L}, la forme de Painlevé {h} donne "
                      "dE/dt = −∂L/∂t + d(T₁ + 2 T₀)/dt :",
                      "With {T} (the parts of degree 2, 1 and 0 in q̇) and {L}, Painlevé's form {h} gives "
                      "dE/dt = −∂L/∂t + d(T₁ + 2 T₀)/dt:"),
    "cond conservative": ("le système est conservatif", "the system is conservative"),
    "cond no work": ("les efforts non conservatifs ne travaillent pas", "the non-conservative forces do no work"),
    "replace": ("L'équation de Lagrange relative à {q} peut être remplacée par {what}.",
                "The Lagrange equation of {q} may be replaced by {what}."),
    "replace one": ("{what} peut remplacer l'une des équations {eqs}.",
                    "{what} may replace one of the equations {eqs}."),
    "the energy integral": ("l'intégrale première de l'énergie", "the energy integral"),
    "the jacobi integral": ("l'intégrale de Jacobi h", "the Jacobi integral h"),
    "or": ("ou", "or"),
    "coriolis zero": ("Les efforts d'inertie de Coriolis ne dérivent pas d'une énergie potentielle, mais ils sont "
                      "orthogonaux à la vitesse par rapport à {R} et ne développent aucune puissance réelle ; ici "
                      "leurs composantes généralisées sont nulles, {Q}.",
                      "The Coriolis inertial forces do not derive from a potential energy, but they are orthogonal "
                      "to the velocity relative to {R} and do no work (their real power is zero); here their generalized forces "
                      "are zero, {Q}."),
    "coriolis gyroscopic": ("Les efforts d'inertie de Coriolis ne dérivent pas d'une énergie potentielle, mais ils "
                            "sont orthogonaux à la vitesse par rapport à {R} et ne développent aucune puissance "
                            "réelle : leurs composantes généralisées {Q} ne sont pas nulles mais gyroscopiques, {P} ; "
                            "elles restent dans les {nc}.",
                            "The Coriolis inertial forces do not derive from a potential energy, but they are "
                            "orthogonal to the velocity relative to {R} and do no work (their real power is zero): their generalized "
                            "forces {Q} are not zero but gyroscopic, {P}; they stay in the {nc}."),
    "coriolis jacobi": (" L'intégrale de Jacobi {h} est donc conservée (voir « Intégrales premières »).",
                        " The Jacobi integral {h} is therefore conserved (see “First integrals”)."),
    "no integral": ("Aucune intégrale première n'apparaît : aucun paramètre n'est cyclique, et {why}.",
                    "No first integral appears: no parameter is cyclic, and {why}."),
    "no integral but cyclic": ("Aucune intégrale première n'apparaît : aucun paramètre cyclique ne donne d'intégrale "
                               "(ci-dessus), et {why}.",
                               "No first integral appears: no cyclic parameter gives one (above), and {why}."),
    "cyclic driven": ("{q} est un paramètre cyclique, {dL}, mais cela ne suffit pas pour intégrer {eq} : {why}.",
                      "{q} is cyclic, {dL}, but that does not suffice to integrate {eq}: {why}."),
    "row acts": ("une liaison complémentaire agit sur lui, {a}", "a complementary constraint acts on it, {a}"),
    "why time": ("le lagrangien dépend explicitement du temps", "the Lagrangian depends on the time explicitly"),
    "why work": ("des efforts non conservatifs travaillent", "non-conservative forces do work"),
    "why constraints": ("les réactions des liaisons complémentaires travaillent",
                        "the reactions of the complementary constraints do work"),
    # -- the Newton–Euler check -------------------------------------------------------------------
    "check intro": ("Ces équations de Lagrange peuvent être retrouvées en appliquant les théorèmes généraux à chaque "
                    "constituant de (Σ) par rapport à {R0} galiléen, projetés sur les directions associées à chaque "
                    "paramètre :", "These Lagrange equations can be recovered by applying the "
                    "Newton–Euler theorems to each part of (Σ) relative to the Galilean frame {R0}, projected onto the "
                    "directions that go with each parameter:"),
    "check intro moving": ("Ces équations de Lagrange peuvent être retrouvées en appliquant les théorèmes généraux par "
                           "rapport à {R0}, non galiléen, en ajoutant aux efforts donnés les efforts d'inertie de "
                           "Coriolis et d'entraînement, projetés sur les directions associées à chaque paramètre :",
                           "These Lagrange equations can be recovered by applying the Newton–Euler theorems "
                           "relative to {R0}, which is not Galilean, adding the Coriolis and transport inertial forces "
                           "to the applied forces, and projecting them onto the directions that go with each "
                           "parameter:"),
    "moment theorem": ("Théorème du moment dynamique en {P} de {S} :", "Angular momentum theorem about {P} for {S}:"),
    "moment theorem parallel": ("Théorème du moment dynamique en {P} de {S} ; le point {P} est mobile dans {R}, mais "
                                "sa vitesse est parallèle à celle de {G}, donc {term} et le moment dynamique est la "
                                "dérivée du moment cinétique.",
                                "Angular momentum theorem about {P} for {S}; {P} moves in {R}, but parallel to "
                                "{G}, so {term} and the dynamic moment is the derivative of the angular momentum."),
    "moment theorem moving": ("Théorème du moment dynamique en {P} de {S} ; le point {P} étant mobile dans {R}, le "
                              "moment dynamique n'est pas la dérivée du moment cinétique : il s'en écarte de {term}.",
                              "Angular momentum theorem about {P} for {S}; {P} moves in {R}, so the dynamic "
                              "moment is not the derivative of the angular momentum: they differ by {term}."),
    "resultant theorem": ("Théorème de la résultante dynamique pour {P} :", "Resultant theorem for {P}:"),
    "by moment": ("{eq} par projection du théorème du moment dynamique en {P}{of} sur {e} :",
                  "{eq} by projecting the angular momentum theorem about {P}{of} onto {e}:"),
    "by resultant": ("{eq} par projection du théorème de la résultante dynamique{of} sur {e} :",
                     "{eq} by projecting the resultant theorem{of} onto {e}:"),
    "by power": ("{eq} par projection des théorèmes{of} sur les vitesses partielles de {q} (puissance virtuelle) :",
                 "{eq} by projecting the theorems{of} onto the partial velocities of {q} (virtual power):"),
    "by power note": ("{names}, donnés par leurs composantes généralisées, entrent dans chaque projection par ces "
                      "composantes (leur puissance virtuelle).",
                      "{names}, given by their generalized forces, enter each projection through those (their "
                      "virtual power)."),
    "by power note one": ("{names}, donné par ses composantes généralisées, entre dans chaque projection par ces "
                          "composantes (sa puissance virtuelle).",
                          "{names}, given by its generalized forces, enters each projection through those (its "
                          "virtual power)."),
    "of": (" de {names}", " of {names}"),
    "check summarized": ("la projection des quantités d'accélération, {G} ({k} termes), et celle des efforts, "
                         "{Q} ({k2} termes), trop longues pour être écrites ici, redonnent, développées, les deux "
                         "membres de {eq} (étape 6) :",
                         "the projection of the mass-times-accelerations, {G} ({k} terms), and that of the efforts, "
                         "{Q} ({k2} terms), too long to print here, give back, expanded, the two members of {eq} "
                         "(step 6):"),
    "check summarized left": ("la projection des quantités d'accélération, {G} ({k} termes), trop longue pour être "
                              "écrite ici, redonne, développée, le premier membre de {eq} (étape 6), et celle des "
                              "efforts, {Q}, son second membre :",
                              "the projection of the mass-times-accelerations, {G} ({k} terms), too long to print "
                              "here, gives back, expanded, the left member of {eq} (step 6), and that of the efforts, "
                              "{Q}, its right member:"),
    "check failed": ("Désaccord : la projection ne redonne pas {eq}.", "Disagreement: the projection does not give "
                     "{eq} back."),
    "constraint actions": ("liaisons", "constraints"),
    "notes": ("Expressions longues", "Long expressions"),
    "perfect drop": ("Les liaisons étant parfaites, leurs actions disparaissent de chaque projection.",
                     "The constraints being ideal (workless), their actions drop out of every projection."),
    "perfect drop principal": ("Les liaisons principales étant parfaites, leurs actions disparaissent de chaque "
                               "projection ; celles des liaisons complémentaires y restent, par les multiplicateurs.",
                               "The principal constraints being ideal (workless), their actions drop out of every "
                               "projection; those of the complementary constraints stay, through the multipliers."),
    "drop not perfect": ("Les actions des liaisons disparaissent de chaque projection, sauf leurs frottements, qui "
                         "y restent avec les efforts donnés.",
                         "The actions of the constraints drop out of every projection, except their friction, which "
                         "stays with the applied forces."),
    "fixed axis": ("{e} étant fixe dans {R0} et {O} fixe, la projection du moment dynamique sur {e} est la dérivée de "
                   "celle du moment cinétique, qui est la quantité de mouvement généralisée :",
                   "Since {e} and {O} are fixed in {R0}, the projection of the dynamic moment onto {e} is the derivative "
                   "of that of the angular momentum, which is the generalized momentum:"),
    "pvv": ("Le principe des puissances virtuelles, pour tout champ de vitesses virtuelles compatible avec les "
            "liaisons principales :",
            "The principle of virtual power, for every virtual velocity field compatible with the principal "
            "constraints:"),
    "gamma": ("où {gamma} est la composante généralisée des quantités d'accélération de (Σ) par rapport à {R}, "
              "et {Q} celle de tous les efforts ; d'où les équations de Lagrange :",
              "where {gamma} is the generalized component of the mass-times-acceleration of (Σ) relative to {R} "
              "(its generalized inertia term), and {Q} that of all the forces and moments; hence Lagrange's "
              "equations:"),
    "top moment": ("{R0} étant galiléen, le théorème du moment dynamique en {O} de ({S}) par rapport à {R0} "
                   "s'écrit :", "{R0} being Galilean, the angular momentum theorem about {O} for ({S}) "
                   "relative to {R0} reads:"),
    "fixed point moment": ("La réaction {R} s'applique en {O} : son moment en {O} est nul, {OO}.",
                           "The reaction {R} acts at {O}: its moment about {O} is zero, {OO}."),
    "whole system": ("(Σ)", "(Σ)"),
    # -- simulation, appendix, sizes --------------------------------------------------------------
    "figure": ("Figure {k} : {caption}", "Figure {k}: {caption}"),
    "scene statement": ("Le système dans sa position initiale : repères, points et angles (vue 3D, à tourner "
                        "à la souris)", "The system in its initial position: frames, points and angles (3-D view, "
                        "turn it with the mouse)"),
    "scene motion": ("Le mouvement simulé (vue 3D : lecture, curseur du temps, traces, vecteurs)",
                     "The simulated motion (3-D view: play, time slider, traces, vectors)"),
    "matrix large": ("Les équations de Lagrange s'écrivent {form} ; la matrice {n} a {k} coefficients non nuls "
                     "(triangle supérieur), trop pour les écrire ici : la commande {cmd} les donne, avec F.",
                     "The Lagrange equations read {form}; the {n} matrix has {k} nonzero entries (upper "
                     "triangle), too many to print here: the command {cmd} gives them, with F."),
    "matrix intro multipliers": ("Les équations de Lagrange s'écrivent {form}, où F ne contient que les efforts donnés "
                                 "et {A} est la matrice des coefficients des liaisons complémentaires (étape 7), "
                                 "de multiplicateurs {lam} ; avec :",
                                 "The Lagrange equations read {form}, where F holds the applied forces only and {A} "
                                 "is the matrix of the complementary constraints' coefficients (step 7), with the "
                                 "multipliers {lam}; with:"),
    "matrix intro multiplier": ("Les équations de Lagrange s'écrivent {form}, où F ne contient que les efforts donnés, "
                                "{A} est la ligne des coefficients de la liaison complémentaire (étape 7) et {lam} son "
                                "multiplicateur ; avec :",
                                "The Lagrange equations read {form}, where F holds the applied forces only, {A} is the "
                                "row of the complementary constraint's coefficients (step 7) and {lam} its multiplier; "
                                "with:"),
    "matrix intro": ("Les équations de Lagrange s'écrivent {form}, avec :", "The Lagrange equations read {form}, with:"),
    "show full": ("{label} : {k} lignes — afficher en entier", "{label}: {k} lines — show in full"),
    "show more": ("les {k} autres liaisons — afficher", "the {k} other constraints — show"),
    "show all": ("{label} — afficher ({k})", "{label} — show ({k})"),
    "terms": ("termes", "terms"),
    "long expression": ("expression longue", "long expression"),
    "see": ("voir", "see"),
    "refs": ("{first} à {last}", "{first} to {last}"),
    "full forms": ("{label} : formes complètes {refs}", "{label}: full forms {refs}"),
    "show it": ("{what} — afficher", "{what} — show"),
    "appendix full": ("Annexe : formes complètes", "Appendix: full forms"),
    "full forms note": ("Une expression trop longue pour être écrite dans son équation y est résumée, comme {sample} ; "
                        "sa forme complète ({refs}) est donnée sous l'équation (en LaTeX, en annexe).",
                        "An expression too long to print in its equation is summarized there, as {sample}; its full "
                        "form ({refs}) is given under the equation (in LaTeX, in an appendix)."),
    "full forms left": ("Les formes complètes sont limitées à {budget} caractères de LaTeX en tout : {k} autres "
                        "résumés, comme {sample}, restent tels quels. La commande {cmd} (ou la fonction {fn}) donne "
                        "toutes les équations en entier.",
                        "The full forms are limited to {budget} characters of LaTeX in all: {k} other summaries, "
                        "as {sample}, stay as they are. The command {cmd} (or the function {fn}) gives every "
                        "equation in full."),
    # -- small motions (opt-in section) ------------------------------------------------------------
    "small title": ("Petits mouvements au voisinage d'une position d'équilibre", "Small motions about an equilibrium"),
    "small title steady": ("Petits mouvements au voisinage d'un mouvement stationnaire",
                           "Small motions about a steady motion"),
    "small intro": ("Au voisinage de la position d'équilibre {point}, on pose {dq} avec δq petit, et l'on ne garde "
                    "des équations de Lagrange que les termes du premier ordre en δq et δq̇ (les efforts y sont "
                    "nuls à l'ordre zéro, puisque la position est d'équilibre).",
                    "About the equilibrium {point}, write {dq} with δq small, and keep only the first-order terms "
                    "in δq and δq̇ of Lagrange's equations (the forces vanish at order zero, since the position is "
                    "an equilibrium)."),
    "small intro steady": ("Au voisinage du mouvement stationnaire {point}, on pose {dq} avec δq petit, et l'on ne "
                           "garde des équations de Lagrange que les termes du premier ordre en δq et δq̇.",
                           "About the steady motion {point}, write {dq} with δq small, and keep only the "
                           "first-order terms in δq and δq̇ of Lagrange's equations."),
    "small dependent": ("Les liaisons complémentaires éliminent {names} (paramètres et vitesses dépendants).",
                        "The complementary constraints eliminate {names} (dependent coordinates and speeds)."),
    "small equations": ("Les équations linéarisées, de la forme {form}, sont :",
                        "The linearized equations, of the form {form}, are:"),
    "small matrices": ("soit, sous forme matricielle :", "that is, in matrix form:"),
    "small matrices defined": ("{M} est la matrice de masse en {q0} ; {D} et {G}, parties symétrique et "
                               "antisymétrique de {dF}, sont l'amortissement et les termes gyroscopiques ; {K} et {N}, "
                               "parties symétrique et antisymétrique de {dFq}, sont la raideur ({KU} quand les efforts "
                               "dérivent d'une énergie potentielle) et les termes circulatoires.",
                               "{M} is the mass matrix at {q0}; {D} and {G}, the symmetric and skew parts of {dF}, are "
                               "the damping and the gyroscopic terms; {K} and {N}, the symmetric and skew parts of "
                               "{dFq}, are the stiffness ({KU} when the efforts derive from a potential energy) and the "
                               "circulatory terms."),
    "small matrices defined reduced": ("Ces matrices portent sur les paramètres indépendants, les autres étant "
                                       "éliminés par les liaisons complémentaires : {M} est la matrice de masse "
                                       "réduite ; {D} et {G} sont les parties symétrique et antisymétrique des termes "
                                       "en {dqd} (amortissement et termes gyroscopiques), {K} et {N} celles des termes "
                                       "en {dq} (raideur et termes circulatoires).",
                                       "These matrices act on the independent coordinates, the others being "
                                       "eliminated by the complementary constraints: {M} is the reduced mass matrix; "
                                       "{D} and {G} are the symmetric and skew parts of the terms in {dqd} (damping and "
                                       "gyroscopic terms), {K} and {N} those of the terms in {dq} (stiffness and "
                                       "circulatory terms)."),
    "small B defined": (" {B} donne l'action des entrées {u}.", " {B} gives the action of the inputs {u}."),
    "small closed point": ("Cette position d'équilibre s'écrit {defs}, c'est-à-dire {rels}.",
                           "This equilibrium is {defs}, that is {rels}."),
    "small closed point condition": ("Cette position d'équilibre s'écrit {defs}, c'est-à-dire {rels} ; elle n'existe "
                                     "que si {cond}.",
                                     "This equilibrium is {defs}, that is {rels}; it exists only if {cond}."),
    "small closed point eliminated": ("Cette position d'équilibre s'écrit {defs}, c'est-à-dire {rels}. Les "
                                      "coefficients ci-dessous sont écrits avec elle, en remplaçant {subs} d'après "
                                      "cette relation.",
                                      "This equilibrium is {defs}, that is {rels}. The coefficients below are "
                                      "written with it, replacing {subs} by that relation."),
    "small closed point condition eliminated": ("Cette position d'équilibre s'écrit {defs}, c'est-à-dire {rels} ; "
                                                "elle n'existe que si {cond}. Les coefficients ci-dessous sont écrits "
                                                "avec elle, en remplaçant {subs} d'après cette relation.",
                                                "This equilibrium is {defs}, that is {rels}; it exists only if {cond}. "
                                                "The coefficients below are written with it, replacing {subs} by "
                                                "that relation."),
    "small numeric": ("Les coefficients sont écrits avec les valeurs numériques des constantes : la position "
                      "n'est d'équilibre que pour ces valeurs.",
                      "The coefficients are written with the numerical values of the constants: the position is "
                      "an equilibrium for these values only."),
    "small numeric long": ("Les coefficients sont écrits avec les valeurs numériques des constantes : écrit avec "
                           "les lettres, le plus long compterait {n} caractères.",
                           "The coefficients are written with the numerical values of the constants: in letters, the "
                           "longest would run to {n} characters."),
    "small first order": ("Les équations réduites ne sont que du premier ordre ({why}) ; elles s'écrivent {x}.",
                          "The reduced equations are first order only ({why}); they read {x}."),
    "small one pulsation": ("L'équation est celle d'un oscillateur harmonique en {q}, de pulsation propre :",
                            "This is the equation of a harmonic oscillator in {q}, with the natural pulsation:"),
    "small omega value": ("soit numériquement {omega}, et une période des petites oscillations {T}.",
                          "that is {omega}, and a period of the small oscillations {T}."),
    "small pulsations": ("Les pulsations propres sont les racines positives de {det} :",
                         "The natural pulsations are the positive roots of {det}:"),
    "small eigenvalues": ("Les valeurs propres de la matrice d'état A sont {lam}.",
                          "The eigenvalues of the state matrix A are {lam}."),
    "small lagrange dirichlet": ("La matrice {K} est définie positive : l'énergie potentielle {U} admet un minimum "
                                 "strict en {q0}. D'après le théorème de Lagrange–Dirichlet, la position d'équilibre "
                                 "est stable.",
                                 "The matrix {K} is positive definite: the potential energy {U} has a strict minimum "
                                 "at {q0}. By the Lagrange–Dirichlet theorem, the equilibrium is stable."),
    "small lagrange dirichlet neutral": ("La matrice {K}, restreinte aux coordonnées {names} qui restent une fois "
                                         "mises à part les directions neutres, est définie positive : l'énergie "
                                         "potentielle {U} admet un minimum strict en ces coordonnées. D'après le "
                                         "théorème de Lagrange–Dirichlet, la position d'équilibre est stable pour "
                                         "elles ; les directions neutres, elles, peuvent dériver (un décalage le long "
                                         "de l'une d'elles est un autre équilibre).",
                                         "The matrix {K}, restricted to the coordinates {names} left once the neutral "
                                         "directions are set aside, is positive definite: the potential energy {U} has "
                                         "a strict minimum in those coordinates. By the Lagrange–Dirichlet theorem, the "
                                         "equilibrium is stable in them; the neutral directions may drift (a shift "
                                         "along one of them is another equilibrium)."),
    "small kelvin tait": ("La matrice K est définie positive et les autres termes sont gyroscopiques (G "
                          "antisymétrique, de puissance nulle) : l'équilibre est stable (théorème de "
                          "Kelvin–Tait–Chetaev).",
                          "K is positive definite and the other terms are gyroscopic (G skew, doing no work): the "
                          "equilibrium is stable (Kelvin–Tait–Chetaev theorem)."),
    "small gyroscopic": ("La matrice K n'est pas définie positive (plus petite valeur propre {kmin}), mais les termes "
                         "gyroscopiques rendent toutes les valeurs propres simples et imaginaires pures : stabilité "
                         "gyroscopique, au premier ordre (la linéarisation ne décide pas du mouvement non linéaire).",
                         "K is not positive definite (smallest eigenvalue {kmin}), but the gyroscopic terms make every "
                         "eigenvalue simple and purely imaginary: gyroscopic stabilisation, to first order (the "
                         "linearization does not decide the nonlinear motion)."),
    "small first order stable": ("Toutes les valeurs propres restantes sont simples et imaginaires pures : le "
                                 "mouvement linéarisé reste borné, stable au premier ordre (pour un mouvement "
                                 "stationnaire à moments conservés fixés, c'est la condition de Routh sur le "
                                 "potentiel effectif) ; la linéarisation ne décide pas du mouvement non linéaire.",
                                 "Every eigenvalue left is simple and purely imaginary: the linearized motion stays "
                                 "bounded, stable to first order (for a steady motion at fixed conserved momenta, "
                                 "this is Routh's condition on the effective potential); the linearization does not "
                                 "decide the nonlinear motion."),
    "small neutral": ("Les directions {names} sont neutres (valeur propre nulle : coordonnées ignorables ou "
                      "quantités conservées) ; elles sont mises à part.",
                      "The directions {names} are neutral (eigenvalue 0: ignorable coordinates or conserved "
                      "quantities); they are set aside."),
    "small neutral one": ("La direction {names} est neutre (valeur propre nulle : coordonnée ignorable ou quantité "
                          "conservée) ; elle est mise à part.",
                          "The direction {names} is neutral (eigenvalue 0: an ignorable coordinate or a conserved "
                          "quantity); it is set aside."),
    "small no values": ("Les pulsations et la stabilité demandent une valeur pour {names}.",
                        "The pulsations and the stability need a value for {names}."),
    "small momentum": ("un moment conservé", "a conserved momentum"),
    "small momenta": ("{k} moments conservés", "{k} conserved momenta"),
    "small eigenvalues left": ("Les autres valeurs propres de la matrice d'état A sont {lam}.",
                               "The other eigenvalues of the state matrix A are {lam}."),
    "small unstable no minimum": ("La matrice {K} n'est pas définie positive (plus petite valeur propre {kmin}) : "
                                  "{U} n'a pas de minimum en {q0}, et la valeur propre {lam} a une partie réelle "
                                  "positive : les petits mouvements croissent, la position d'équilibre est "
                                  "instable.",
                                  "The matrix {K} is not positive definite (smallest eigenvalue {kmin}): {U} has no "
                                  "minimum at {q0}, and the eigenvalue {lam} has a positive real part: small motions "
                                  "grow, the equilibrium is unstable."),
    "small unstable": ("La valeur propre {lam} a une partie réelle positive : les petits mouvements croissent, le "
                       "mouvement est instable (première méthode de Lyapunov).",
                       "The eigenvalue {lam} has a positive real part: small motions grow, the motion is unstable "
                       "(Lyapunov's first method)."),
    "small asymptotic": ("Toutes les valeurs propres ont une partie réelle négative (la plus grande : {lam}) : les "
                         "petits mouvements s'amortissent, le mouvement est asymptotiquement stable.",
                         "Every eigenvalue has a negative real part (the largest: {lam}): small motions decay, the "
                         "motion is asymptotically stable."),
    "small secular": ("La valeur propre 0 n'est pas semi-simple : une fois mises à part les coordonnées ignorables, "
                      "la matrice A a pour elle un bloc de Jordan de taille {k}, de sorte qu'une perturbation {start} "
                      "fait croître {end} comme {t}. Le mouvement linéarisé n'est pas borné, bien qu'aucune valeur "
                      "propre n'ait de partie réelle positive : il est instable (croissance séculaire).",
                      "The eigenvalue 0 is not semisimple: once the ignorable coordinates are set aside, the matrix A "
                      "has a Jordan block of size {k} for it, so that a perturbation {start} makes {end} grow like "
                      "{t}. The linearized motion is unbounded, although no eigenvalue has a positive real part: it "
                      "is unstable (secular growth)."),
    "small marginal": ("Les valeurs propres sont sur l'axe imaginaire (ou l'une est nulle ou multiple) : la "
                       "linéarisation ne permet pas de conclure sur la stabilité (cas critique).",
                       "The eigenvalues lie on the imaginary axis (or one is zero or repeated): the linearization "
                       "does not decide the stability (critical case)."),
    "precession": ("Précession du plan d'oscillation : M étant isotrope et G antisymétrique, le changement de "
                   "variables {change}, où R est la rotation d'angle {angle} dans le plan {plane}, de {q1} vers {q2}, "
                   "élimine les termes gyroscopiques pour la vitesse {wp} ci-dessous (théorème de Larmor) : p oscille "
                   "dans un plan fixe, et le plan d'oscillation de δq tourne à la vitesse angulaire",
                   "Precession of the plane of oscillation: M being isotropic and G skew, the change of variables "
                   "{change}, R the rotation by {angle} in the plane {plane}, from {q1} towards {q2}, removes the "
                   "gyroscopic terms for the rate {wp} below (Larmor's theorem): p oscillates in a fixed plane, and "
                   "the plane of oscillation of δq turns at the angular rate"),
    "precession first order": ("Précession du plan d'oscillation : M étant isotrope et G antisymétrique, le "
                               "changement de variables {change}, où R est la rotation d'angle {angle} dans le plan "
                               "{plane}, de {q1} vers {q2}, élimine les termes gyroscopiques pour la vitesse {wp} "
                               "ci-dessous (théorème de Larmor) ; K n'étant isotrope qu'à des termes d'ordre 2 en "
                               "{s} près, le plan d'oscillation tourne, au premier ordre en {s}, à la vitesse angulaire",
                               "Precession of the plane of oscillation: M being isotropic and G skew, the change of "
                               "variables {change}, R the rotation by {angle} in the plane {plane}, from {q1} towards "
                               "{q2}, removes the gyroscopic terms for the rate {wp} below (Larmor's theorem); K "
                               "being isotropic up to terms of second order in {s}, the plane of oscillation turns, "
                               "to first order in {s}, at the angular rate"),
    "summaries": ("{sample} : expression trop longue pour être écrite ici ; la commande {cmd} (ou la fonction "
                  "{fn}) la donne en entier.", "{sample}: an expression too long to print here; the command "
                  "{cmd} (or the function {fn}) gives it in full."),
}


#: The engine's own load names (the inertial forces) and the usual names of the examples and the
#: zoo, as each language writes them; any other name is the user's and is kept as it is.
_LOAD_NAMES: dict[str, tuple[str, str]] = {
    "weight": ("poids", "weight"),
    "gravity": ("pesanteur", "gravity"),
    "Coriolis": ("Coriolis", "Coriolis"),
    "entrainment": ("entraînement", "transport"),
    "spring": ("ressort", "spring"),
    "damper": ("amortisseur", "damper"),
    "friction": ("frottement", "friction"),
    "drag": ("traînée", "drag"),
    "torque": ("couple", "torque"),
    "motor": ("moteur", "motor"),
    "actuators": ("actionneurs", "actuators"),
    "push": ("poussée", "push"),  # a URDF robot's joint torques (model/urdf.py)
    "joint_damping": ("amortissement des liaisons", "joint damping"),
}


class Words:
    """The phrases of one language: ``w("key", name=value, ...)`` gives runs, ``w.text`` plain text."""

    def __init__(self, lang: str) -> None:
        if lang not in LANGUAGES:
            raise ValueError(f"language must be one of {', '.join(LANGUAGES)}, not {lang!r}")
        self.lang = lang
        self._index = LANGUAGES.index(lang)

    def has(self, key: str) -> bool:
        return key in _PHRASES

    def template(self, key: str) -> str:
        return _PHRASES[key][self._index]

    def text(self, key: str, **values: str) -> str:
        return self.template(key).format(**values)

    def __call__(self, key: str, **values: Run | Runs) -> Runs:
        """The phrase ``key`` as runs, each ``{slot}`` replaced by text, `Math` or runs."""
        out: list[Run] = []
        for k, piece in enumerate(re.split(r"\{(\w+)\}", self.template(key))):
            if k % 2 == 0:
                if piece:
                    out.append(piece)
                continue
            value = values[piece]
            out.extend(value if isinstance(value, tuple) else (value,))
        return _merge(out)

    def join(self, items: Sequence[Run | Runs]) -> Runs:
        """``a, b et c`` / ``a, b and c``."""
        parts: list[Run] = []
        last = " " + self.template("and") + " "
        for k, item in enumerate(items):
            if k:
                parts.append(last if k == len(items) - 1 else ", ")
            parts.extend(item if isinstance(item, tuple) else (item,))
        return _merge(parts)

    def join_or(self, items: Sequence[Run | Runs]) -> Runs:
        """``a, b ou c`` / ``a, b or c``."""
        parts: list[Run] = []
        last = " " + self.template("or") + " "
        for k, item in enumerate(items):
            if k:
                parts.append(last if k == len(items) - 1 else ", ")
            parts.extend(item if isinstance(item, tuple) else (item,))
        return _merge(parts)

    def load(self, name: str) -> str:
        """A load's name as this language writes it: the engine's and the usual ones translated, the user's kept."""
        pair = _LOAD_NAMES.get(name)
        return pair[self._index] if pair is not None else name

    def number(self, value: float, digits: int = 6) -> str:
        """A number as this language writes it (decimal comma in French, 5·10⁻⁵ rather than 5e-05), with at
        most ``digits`` significant digits (4 for a value computed from the model: K ≈ 0,4388 J·s)."""
        text = f"{value:.{digits}g}"
        mantissa, e, exponent = text.partition("e")
        if e:
            power = str(int(exponent)).translate(_SUPERSCRIPTS)
            text = ("" if mantissa in ("1", "-1") else mantissa + "·") + "10" + power
            if mantissa == "-1":
                text = "-" + text
        text = text.replace("-", "\u2212")  # a minus sign, not a hyphen
        return text.replace(".", ",") if self.lang == "fr" else text


_SUPERSCRIPTS = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def _merge(runs: Sequence[Run]) -> Runs:
    """Adjacent text runs joined into one."""
    out: list[Run] = []
    for r in runs:
        if isinstance(r, str) and out and isinstance(out[-1], str):
            out[-1] = out[-1] + r
        elif r != "":
            out.append(r)
    return tuple(out)
