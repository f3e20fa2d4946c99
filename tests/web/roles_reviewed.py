"""Who may call each operation: the reviewed table.

The route table must equal this table exactly (test_roles.py). Changing who may call an
operation therefore takes two edits, one of them here, in review; a route opened to every role
by mistake fails the test instead of passing it (the old test compared each route with its own
declaration). Roles: operator, supervisor, auditor, admin, or anonymous (no sign-in)."""

from __future__ import annotations

REVIEWED_ROLES: dict[str, tuple[str, ...]] = {
    # The procedure library: operators save versions, supervisors sign decisions
    # on them, every role reads (auditors included).
    "listProcedures": ("operator", "supervisor", "auditor", "admin"),
    "getProcedure": ("operator", "supervisor", "auditor", "admin"),
    "saveProcedure": ("operator",),
    "prepareProcedureDecision": ("supervisor",),
    "signProcedureDecision": ("supervisor",),
    "getVersionProcedures": ("operator", "supervisor", "auditor", "admin"),
    # Rehearsal campaigns: operators and supervisors start and cancel their own;
    # every role reads; only the submitting operator attaches one to a submission.
    "startCampaign": ("operator", "supervisor"),
    "cancelCampaign": ("operator", "supervisor"),
    "listCampaigns": ("operator", "supervisor", "auditor", "admin"),
    "getCampaign": ("operator", "supervisor", "auditor", "admin"),
    "campaignProbabilities": ("operator", "supervisor", "auditor", "admin"),
    "attachCampaign": ("operator",),
    "listAttachedCampaigns": ("operator", "supervisor", "auditor", "admin"),
    # Whether a fault can change an outcome of a version: read as the version is.
    "faultReach": ("operator", "supervisor", "auditor", "admin"),
    # Chart registry and plan view: admins write, every signed-in role reads.
    "listCharts": ("operator", "supervisor", "auditor", "admin"),
    "exportCharts": ("operator", "supervisor", "auditor", "admin"),
    "exportChartsKml": ("operator", "supervisor", "auditor", "admin"),
    "putChart": ("admin",),
    "importCharts": ("admin",),
    "deleteChart": ("admin",),
    "planView": ("operator", "supervisor", "auditor", "admin"),
    # POST /api/submissions/{submission_id}/rehearsal
    "attachRehearsal": ("operator",),
    # POST /api/auth/password
    "changePassword": ("operator", "supervisor", "auditor", "admin"),
    # POST /api/rehearsals/{rehearsal_id}/skip
    "skipRehearsal": ("operator", "supervisor"),
    # POST /api/rehearsals/{rehearsal_id}/outcome
    "chooseOutcome": ("operator", "supervisor"),
    # POST /api/missions
    "createMission": ("operator",),
    # POST /api/tokens
    "createToken": ("operator", "supervisor", "auditor", "admin"),
    # POST /api/users
    "createUser": ("admin",),
    # POST /api/missions/{mission_id}/versions
    "createVersion": ("operator",),
    # DELETE /api/missions/{mission_id}
    "deleteMission": ("operator",),
    # GET /api/audit/bundle
    "exportBundle": ("supervisor", "auditor", "admin"),
    # GET /api/missions/{mission_id}/versions/{number}/vehicle/{format}[/{name}]
    "getVehicleExport": ("operator", "supervisor", "auditor", "admin"),
    "downloadVehicleExport": ("operator", "supervisor", "auditor", "admin"),
    # POST /api/missions/{mission_id}/versions/{number}/executions
    "recordExecution": ("operator", "supervisor"),
    # GET /api/approvals/{approval_id}/executions: the record page's executions
    "getRecordExecutions": ("supervisor", "auditor", "admin"),
    # GET /api/missions/{mission_id}/versions/{number}/package
    "downloadPackage": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/missions/{mission_id}/export
    "exportMission": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/approvals/{approval_id}
    "getApproval": ("supervisor", "auditor", "admin"),
    # GET /api/log/checkpoint
    "getCheckpoint": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/client-config
    "getClientConfig": ("operator", "supervisor", "auditor", "admin"),
    "getCosignedCheckpoint": ("operator", "supervisor", "auditor", "admin"),
    "addCosignature": ("supervisor", "auditor", "admin"),
    # GET /api/log/consistency
    "getConsistencyProof": ("supervisor", "auditor", "admin"),
    # GET /api/missions/{mission_id}/versions/{number}/document
    "getDocument": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/missions/{mission_id}/versions/{number}/document.txt
    "getDocumentText": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/examples/{name}
    "getExample": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/log/inclusion
    "getInclusionProof": ("supervisor", "auditor", "admin"),
    # GET /api/missions/{mission_id}
    "getMission": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/missions/{mission_id}/standing
    "getMissionStanding": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/rehearsals/{rehearsal_id}
    "getRehearsal": ("operator", "supervisor"),
    # GET /api/rehearsal-records/{digest}
    "getRehearsalRecord": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/rehearsal-records/{digest}/replay.html
    "getRehearsalReplay": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/missions/{mission_id}/report
    "getReport": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/submissions/{submission_id}
    "getSubmission": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/missions/{mission_id}/versions/{number}
    "getVersion": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/health
    "health": ("anonymous",),
    # POST /api/import
    "importMission": ("operator",),
    # POST /api/rehearsals/{rehearsal_id}/faults
    "injectFault": ("operator", "supervisor"),
    # GET /api/approvals
    "listApprovals": ("supervisor", "auditor", "admin"),
    # GET /api/events
    "listEvents": ("supervisor", "auditor", "admin"),
    # GET /api/examples
    "listExamples": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/keys
    "listKeys": ("supervisor", "auditor", "admin"),
    # GET /api/log/entries
    "listLogEntries": ("supervisor", "auditor", "admin"),
    # GET /api/missions
    "listMissions": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/missions/{mission_id}/paths
    "listPaths": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/missions/{mission_id}/rehearsal-records
    "listRehearsalRecords": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/submissions
    "listSubmissions": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/tokens
    "listTokens": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/users
    "listUsers": ("admin",),
    # GET /api/vehicles
    "listVehicles": ("operator", "supervisor", "auditor", "admin"),
    # POST /api/auth/login
    "login": ("anonymous",),
    # POST /api/auth/logout
    "logout": ("operator", "supervisor", "auditor", "admin"),
    # POST /api/missions/{mission_id}/plan-problem
    "planProblemFromMission": ("operator",),
    # POST /api/submissions/{submission_id}/statement
    "prepareDecision": ("supervisor",),
    # POST /api/approvals/{approval_id}/statement
    "prepareRevocation": ("supervisor",),
    # PUT /api/vehicles/{vehicle_id}
    "putVehicle": ("admin",),
    # GET /api/vehicles/{vehicle_id}/versions
    "listVehicleVersions": ("operator", "supervisor", "auditor", "admin"),
    # POST /api/read
    "readOrders": ("operator",),
    # POST /api/keys
    "registerKey": ("supervisor",),
    # GET /api/missions/{mission_id}/versions/{number}/review
    "reviewVersion": ("operator", "supervisor", "auditor", "admin"),
    # POST /api/approvals/{approval_id}/revoke
    "revokeApproval": ("supervisor",),
    # POST /api/keys/{key_id}/revoke
    "revokeKey": ("supervisor", "admin"),
    # DELETE /api/tokens/{token_id}
    "revokeToken": ("operator", "supervisor", "auditor", "admin"),
    # POST /api/submissions/{submission_id}/decision
    "signDecision": ("supervisor",),
    # PUT /api/missions/{mission_id}/layout
    "saveLayout": ("operator",),
    # POST /api/plan
    "solvePlan": ("operator", "supervisor", "auditor", "admin"),
    # POST /api/missions/{mission_id}/rehearsals
    "startRehearsal": ("operator", "supervisor"),
    # POST /api/rehearsals/{rehearsal_id}/stop
    "stopRehearsal": ("operator", "supervisor"),
    # POST /api/missions/{mission_id}/versions/{number}/submit
    "submitVersion": ("operator",),
    # PUT /api/missions/{mission_id}/draft
    "updateDraft": ("operator",),
    # PATCH /api/users/{user_id}
    "updateUser": ("admin",),
    # POST /api/validate
    "validateOrders": ("operator", "supervisor", "auditor", "admin"),
    # GET /api/auth/me
    "whoAmI": ("operator", "supervisor", "auditor", "admin"),
    # POST /api/submissions/{submission_id}/withdraw
    "withdrawSubmission": ("operator",),
}
