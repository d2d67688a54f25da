"""The names and provenance of the model's law options (DC force, 2-DOF soil, compaction).

A light module (no heyoka, no numpy) so that the command line lists the choices without
loading the integrator; :mod:`maps.model` implements the laws named here.
"""

#: the form of the compaction option (a resistance growing with depth; docs/model.md)
COMPACTION = ("resistance R(depth) = R0 (1 + depth / soil_depth_scale), R0 = soil_friction (coulomb) or "
              "P_max (drift), depth = -x2 (coulomb: the rig below its start at x2 = 0) or -d (drift: the "
              "slider, the soil front)")

#: the soil laws of the 2-DOF scenes (docs/model.md section 2): name -> provenance
SOIL_LAWS = {
    "viscous": "listings C.4-C.6: F_soil = -soil_c v2 on the rig",
    "coulomb": "dry friction with sticking, limit soil_friction (listing C.14's sign(x)*1000, with sticking added)",
    "drift": "impact with drift (Pavlovskaia, Wiercigroch and Grebogi, Phys. Rev. E 64, 056224, 2001): a "
             "visco-elastic element (k_s, c_s) in series with a plastic slider of threshold P_max; the slider "
             "position d is a state; modes no contact / elastic / progression",
}

#: the DC-force laws (docs/model.md section 1): the three of the 1-DOF chapter, "catalogue" (a
#: saturating law anchored on Table 4.1 and the solenoid's catalogue) and "dynamics-script" (listing
#: C.14's law, centred at the stop): name -> provenance
DC_LAWS = {
    "listing": "listing C.9 as printed: F_dc = -a3 xa^3 + a2 xa^2 - a1 xa + m g (the cubic the thesis' "
               "simulations ran; it flips only the cubic term of eq 4.6)",
    "fit": "eqs 4.6-4.7 as printed: F_dc = -a3 xa^3 - a2 xa^2 + a1 xa + m g (eq 4.6 is the least-squares "
           "odd cubic of Table 4.1, eq 4.7 its negative shifted by the weight; eq 4.7 prints 1.55 N for m g)",
    "measured": "Table 4.1 only: monotone piecewise cubic (PCHIP, Fritsch-Carlson) through the 20 V table, "
                "odd in xa, zero for |xa| > 0.029 m (section 4.2: no effect beyond the measured range); "
                "no weight offset",
    "catalogue": "saturating: F_dc = -F_dc_sat/2 [tanh((xa - u_dc)/(2 s_dc)) + tanh((xa + u_dc)/(2 s_dc))], "
                 "odd in xa, plateau F_dc_sat = the catalogue's 750 g at 24 V DC (Table 3.1) times (20/24)^2; "
                 "u_dc, s_dc least squares on Table 4.1 (maps/data/fit_dc_catalogue.py, output "
                 "maps/data/dc_catalogue_fit.json); no weight offset",
    "dynamics-script": "listing C.14 (the thesis' Dynamics script, seed line 2369): Fspr = -1.4735 s^3 + "
                       "1.652e-14 s^2 - 15.38 s on s, the bar relative to the stop, no offset (d_dc = 0): a soft "
                       "15.38 N/m spring centred at the stop; taken: its force law only, in listing C.9's form "
                       "(+m g cancels the weight in 1 DOF; C.14 is horizontal); not taken: C.14's damping "
                       "C2*(u - x) (a position minus a velocity) and s' = x - v (the rig's and the bar's "
                       "velocities mixed), broken as printed (docs/model.md)",
}

#: optional physical elements (docs/model.md section 1b), off by default (today's model); setting
#: the parameter named here switches the element on: option -> (parameter, what it adds)
ELEMENTS = {
    "air_damping": ("c_air", "free-flight damping: F = -c_air (dr/dt) on the bar (2-DOF: bar against the rig's "
                             "tube, reaction on the rig)"),
    "rear_stop": ("e_rear", "the prototype's rear stop (housing): a Kelvin-Voigt contact with the stop's k, c "
                            "for r > e_rear"),
    "dc_delay": ("tau_dc", "the DC coil's switching delay (antiphase relay): normalised current j_dc, "
                           "dj_dc/dt = (gate - j_dc)/tau_dc, tau_dc = L/R; the DC force scales with j_dc^2"),
}
